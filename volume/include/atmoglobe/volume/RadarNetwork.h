#pragma once
// Many radars as one volume: the coverage index that tells which radars can have data at a place,
// and the overlap rules that turn the values of the radars over a point into one (docs/networks.md).
// GL-free, double precision.
//
// COVERAGE INDEX. A grid of geocentric latitude/longitude cells (the direction of the point from
// the Earth's centre: lon = atan2(y, x), lat = atan2(z, hypot(x, y)); no trigonometry of the
// ellipsoid, so a float twin on the GPU finds the same cell) over the union of the radars' clip
// spheres, each cell listing the radars whose sphere can reach into it. A sphere of radius R
// around c reaches the directions within asin(R / |c|) of c's; a radar is listed in a cell when
// the cell's angular distance from c's direction is at most that plus kCoverageMarginDeg. So the
// index is conservative: a radar not listed in a point's cell has no data at the point, and
// sampling only the listed radars gives exactly what sampling every radar gives
// (RadarNetwork.CoverageIndexListsEveryRadarWithDataAtAPoint). Cost rule: a sample visits the radars of its
// cell only; that number depends on how many radars are over the place, not on how many are in
// the network.
//
// OVERLAP RULES (one value per point, before classification):
//  - WeightedMean: sum_k w_k v_k / sum_k w_k over the radars with an Echo there, with
//    w_k = exp(-(r_k / L)^2), r_k the slant range from radar k (m), L = kMosaicWeightLengthMeters
//    (Zhang, Howard and Gourley 2005, J. Atmos. Oceanic Technol. 22, 30-42, the multiple-radar
//    mosaic of NOAA's NMQ/MRMS: a Gaussian weight in distance with L = 50 km; vertically each
//    radar already interpolates between its beam centres, PolarVolume.h). Echo when the echo
//    weight is at least half the weight of the radars that measured the point (Echo or NoEcho),
//    as one radar's rule does between its gates; otherwise NoEcho if any measured it, else NoData.
//  - LowestBeam: the value of the radar whose lowest sweep passes lowest over the point (OPERA's
//    composites take the lowest valid bins): among the radars that measured the point, the least
//    height of the lowest sweep's beam centre at the point's ground distance s from the radar,
//    H_k = h0 + (Re + h0) (cos e0 / cos(e0 + s / Re) - 1) (h0 the antenna's height), the
//    effective-Earth beam of elevation e0 as a straight line over a sphere of radius Re = ke R
//    (Doviak and Zrnic 1993, eq. 2.28); ties: the radar listed first.
//  - Maximum: the largest Echo value; NoEcho if none echoes but one measured; else NoData.
//  - Integrate is the renderers' rule for overlapping volumes (extinctions add, colours weighted
//    by extinction; docs/volume-rendering.md): it has no single value, so it is not a sampler rule.
// Radial velocity and differential phase are relative to each radar (the motion towards that
// antenna, that system's phase offset): no rule combines them (makeRadarNetworkSampler says so).
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::volume {

enum class OverlapRule { Integrate, WeightedMean, LowestBeam, Maximum };

/// "integrate", "mean", "lowest", "max" (the scene and CLI spellings).
const char* toString(OverlapRule rule);
/// Parses those spellings; the error lists them.
Result<OverlapRule> parseOverlapRule(std::string_view text);

inline constexpr double kMosaicWeightLengthMeters = 50000.0;
/// Added to every radar's angular radius in the index (deg; about 11 m): covers the rounding of a
/// float twin's cell lookup.
inline constexpr double kCoverageMarginDeg = 1e-4;

struct CoverageIndex {
  double latMinDeg = 0.0;                ///< geocentric latitude of the first row's south edge
  double lonOriginDeg = 0.0;             ///< longitude of the first column's west edge, in [-180, 180)
  double cellDeg = 1.0;                  ///< cells are cellDeg x cellDeg
  int columns = 0, rows = 0;             ///< the grid spans columns * cellDeg of longitude (at most 360)
  std::vector<std::uint32_t> cellStart;  ///< columns * rows + 1 offsets into `members` (row-major from the south)
  std::vector<std::uint32_t> members;    ///< radar indices, ascending within a cell

  /// The cell holding the direction of `ecef`, -1 outside the grid (no radar reaches there).
  long cellOf(const glm::dvec3& ecef) const;
  /// The radars listed at `ecef` (empty outside).
  std::pair<const std::uint32_t*, const std::uint32_t*> radarsAt(const glm::dvec3& ecef) const;
  std::size_t cellCount() const { return static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows); }
  /// The most radars any cell lists, and the mean over the cells that list any.
  std::size_t maxPerCell() const;
  double meanPerOccupiedCell() const;
};

/// The index of the spheres (a radar's: its clip sphere). cellDeg <= 0: half the smallest
/// angular radius, within [0.02, 2] deg, coarser if the grid would exceed 4 million cells.
CoverageIndex buildCoverageIndex(const std::vector<BoundingSphere>& spheres, double cellDeg = 0.0);

/// The radars of a network as one sampler, combined by a rule (not Integrate). Holds references:
/// the volumes must outlive it.
class RadarNetworkSampler final : public VolumeSampler {
 public:
  RayInterval rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const override;
  VolumeSample sample(const glm::dvec3& ecef, Interpolation interpolation) const override;
  bool provablyEmpty(const glm::dvec3& ecef) const override;
  ValueRange valueRange() const override;
  BoundingSphere boundingSphere() const override;
  std::string description() const override;
  /// The step rule (StepRule.h): the smallest polarCellCrossingMeters of the radars the coverage
  /// index lists at `ecef` whose clip sphere holds it; 0 (the fixed step) where none does.
  double cellCrossingMeters(const glm::dvec3& ecef, const glm::dvec3& unitDirEcef) const override;

  /// The same sample taken by visiting every radar, not the index (for tests and the bench).
  VolumeSample sampleEveryRadar(const glm::dvec3& ecef, Interpolation interpolation) const;
  /// Which radar the rule took the value from (LowestBeam), or the radar of largest weight
  /// (WeightedMean) or value (Maximum); nullopt where the sample is NoData.
  std::optional<std::size_t> leadingRadar(const glm::dvec3& ecef, Interpolation interpolation) const;

  OverlapRule rule() const { return rule_; }
  const CoverageIndex& coverage() const { return index_; }
  std::size_t radarCount() const { return radars_.size(); }
  const PolarVolume& radar(std::size_t k) const { return radars_[k]->polar(); }

 private:
  friend Result<std::unique_ptr<RadarNetworkSampler>> makeRadarNetworkSampler(
      const std::vector<const PolarVolume*>& radars, OverlapRule rule, FieldKind kind, double cellDeg);
  RadarNetworkSampler() = default;
  struct Combined;
  template <class It>
  Combined combine(It first, It last, const glm::dvec3& ecef, Interpolation interpolation) const;

  std::vector<std::unique_ptr<PolarSampler>> radars_;
  std::vector<double> effectiveRadius_;  ///< Re per radar (m)
  OverlapRule rule_ = OverlapRule::WeightedMean;
  CoverageIndex index_;
  BoundingSphere enclosing_;
};

/// A network sampler of `radars` (at least one, all of the same field `kind`). Errors: the
/// Integrate rule (not a one-value rule), a per-radar quantity (velocity, differential phase),
/// no radars.
Result<std::unique_ptr<RadarNetworkSampler>> makeRadarNetworkSampler(const std::vector<const PolarVolume*>& radars,
                                                                     OverlapRule rule, FieldKind kind,
                                                                     double cellDeg = 0.0);

}  // namespace atmoglobe::volume
