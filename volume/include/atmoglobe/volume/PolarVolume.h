#pragma once
// A radar volume prepared for rendering in its own polar geometry, and the sampling rule
// that the GPU marcher (engine: VolumeRendererGL + shaders/volume_march.frag + sample_polar.glsl) and the
// CPU reference renderer (ReferenceRenderer.h) both implement. GL-free.
//
// Layout (what the GPU gets, no Cartesian resampling; the engine packs the values as
// (echo value, echo flag) pairs and the azimuths as rayCoordinateTable, docs/volume-rendering.md):
//  - PPI sweeps only, sorted by elevation; sweeps with the same fixed angle (NEXRAD split
//    cuts) keep the first one that has the field.
//  - values: one layer per sweep, rows = rays sorted by azimuth, columns = gates, padded to
//    maxRays x maxGates (padding is "no data"). Sentinels as in RadarVolume.h: NaN = no data,
//    -inf = no echo, finite = measured value.
//  - Per sweep: elevation, first-gate range, gate spacing, gate count, ray count and the
//    sorted ray azimuths.
//
// SAMPLING RULE at antenna coordinates (range r, azimuth az, elevation el):
//  1. Vertical: with sweeps e_0 < ... < e_{n-1} and half beam width hb = beamWidthDeg / 2:
//     el < e_0 - hb or el > e_{n-1} + hb -> NoData (the cone of silence and the space below
//     the lowest beam stay empty).
//     Nearest: the single sweep k minimising |el - e_k| (ties: the lower one), weight 1.
//     Linear: el <= e_0 -> sweep 0 alone; el >= e_{n-1} -> the top sweep alone; otherwise
//     k with e_k <= el < e_{k+1}, weights (1 - t, t), t = (el - e_k) / (e_{k+1} - e_k).
//  2. In sweep k: gate coordinate g = (r - firstGateRange_k) / gateSpacing_k (gate centres at
//     integers). g < -0.5 or g > gateCount_k - 0.5 -> every texel of this sweep is NoData.
//     Ray coordinate a in [0, rayCount_k): piecewise linear in azimuth between adjacent ray
//     centres (cyclic across 0/360: between the last and the first ray a runs from n-1 to n,
//     and n is ray 0). So irregular azimuth spacing is handled by azimuth, not by index.
//     Nearest: texel (round(a) mod n, clamp(round(g), 0, count-1)).
//     Linear: the 4 texels (floor(a), floor(a)+1 mod n) x (floor(g), floor(g)+1), gate
//     indices clamped to [0, count-1], bilinear weights.
//  3. Combining the texels (1 for nearest; up to 8 for linear, each with its total weight
//     w_i = sweep weight x bilinear weight, sum 1):
//       echoWeight = sum of w_i over measured values; measuredWeight = echoWeight + sum of
//       w_i over no-echo texels.
//       echoWeight >= 0.5 -> Echo, value = sum(w_i v_i over measured) / echoWeight;
//       else measuredWeight >= 0.5 -> NoEcho; else NoData.
//
// TRANSFER FUNCTION (DVR): colour and opacity come from a ColorTable (RGBA, alpha 0..255);
// the table's alpha is the opacity accumulated over `opacityReferenceMeters` of path. For a
// step of s metres the sample's opacity is alpha_s = 1 - (1 - alpha)^(s / reference)
// (opacity correction for step length). NoEcho and NoData contribute nothing.
// Compositing: front to back, premultiplied colour; early termination at alpha >= 0.99.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/OccupancyGrid.h>
#include <atmoglobe/volume/RadarVolume.h>
#include <atmoglobe/volume/StepRule.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume {

struct PolarSweepLayout {
  double elevationDeg = 0.0;          ///< fixed angle of the sweep (degrees)
  double firstGateRangeMeters = 0.0;  ///< centre of gate 0 (m)
  double gateSpacingMeters = 0.0;     ///< (m), > 0
  int gateCount = 0;
  int rayCount = 0;
  std::vector<float> azimuthDeg;  ///< rayCount sorted ray-centre azimuths in [0, 360)
};

struct PolarVolume {
  std::string sourcePath;
  std::string fieldName;
  std::string fieldUnits;
  GeolocationSite site;  ///< antenna on the WGS84 ellipsoid (after resolveSite)
  BeamModel beam;
  double beamWidthDeg = 1.0;             ///< used for the vertical extent (file value, else 1 deg)
  std::vector<PolarSweepLayout> sweeps;  ///< sorted by elevation, strictly increasing
  int maxRays = 0;
  int maxGates = 0;
  std::vector<float> values;    ///< [sweep][ray][gate], sweeps.size() * maxRays * maxGates
  double maxRangeMeters = 0.0;  ///< largest gate-centre range + half a gate, over sweeps
  /// (Addition, reference renderer) Radius (m, ECEF straight-line distance from the antenna) of
  /// a sphere that holds every point whose beam-model range is <= maxRangeMeters within the
  /// vertical extent [e_0 - hb, e_{n-1} + hb]. Larger than maxRangeMeters because the model's
  /// range is a chord of the effective (4/3) Earth, not of the true one: for KLBB the top beam
  /// edge at 460 km lies ~1.5 km beyond a sphere of radius maxRange. Rays are clipped to this
  /// sphere (an acceleration bound only: samplePolar decides what is inside). Computed by
  /// buildPolarVolume from the exact forward geolocation at maxRange over the elevations (0.05
  /// deg grid, both ends) and 8 azimuths, times 1.001.
  double clipRadiusMeters = 0.0;
  float minValue = 0.0f, maxValue = 0.0f;  ///< range of measured values

  float value(int sweep, int ray, int gate) const {
    return values[(static_cast<std::size_t>(sweep) * maxRays + ray) * maxGates + gate];
  }
  std::size_t byteSize() const { return values.size() * sizeof(float); }
};

/// Builds the render layout from a read volume (with values loaded). Errors: no PPI sweep
/// (e.g. an RHI file: "RHI volumes cannot be volume-rendered yet; export or `gates` them"),
/// no values loaded, non-finite geometry.
Result<PolarVolume> buildPolarVolume(const RadarVolume& volume, const SiteResolution& site, const BeamModel& beam);

/// A sample of the rule below (the VolumeSampler states: NoData, NoEcho, Echo).
using PolarSample = VolumeSample;

/// The sampling rule above, in double precision. Azimuth any value (wrapped to [0, 360)).
PolarSample samplePolar(const PolarVolume& v, double rangeMeters, double azimuthDeg, double elevationDeg,
                        Interpolation interpolation);

/// The gate nearest-neighbour sampling reads (the same rule as Interpolation::Nearest: the
/// sweep nearest in elevation within half a beam width of the lowest/highest sweep, the ray
/// nearest in ray coordinate, the gate nearest in range), with its centre and stored value.
/// Indices are into the render layout (sweeps sorted by elevation, rays by azimuth); the
/// centre (elevation, azimuth, range) identifies the gate in the file. nullopt outside the gates.
struct PolarGate {
  int sweep = 0, ray = 0, gate = 0;
  double elevationDeg = 0.0, azimuthDeg = 0.0, rangeMeters = 0.0;
  float value = 0.0f;  ///< as stored: a measurement, kNoEcho or kNoData
};
std::optional<PolarGate> nearestGate(const PolarVolume& v, double rangeMeters, double azimuthDeg, double elevationDeg);

/// Ray coordinate (step 2 of the rule, in [0, rayCount)) of an azimuth (any value, wrapped).
double rayCoordinate(const PolarSweepLayout& sweep, double azimuthDeg);

/// The GPU's azimuth table for one sweep: the ray coordinate at azimuths j * 360 / bins,
/// j = 0..bins (bins + 1 values), made continuous and increasing over [0, 360]: between the
/// last ray and ray 0 *before* the first ray it is a - rayCount (in [-1, 0)), and the value at
/// 360 is the value at 0 plus rayCount. Interpolating it linearly reproduces rayCoordinate
/// except in the bins that hold a ray centre, where the exact function has a kink; the error
/// there is at most bin width x |change of slope| / 4 (PolarVolumeTest, 8192 bins: KLBB
/// 0.0068 rays = 0.0034 deg, its super-resolution azimuths are irregular; AU40 5e-5 rays).
std::vector<float> rayCoordinateTable(const PolarSweepLayout& sweep, int bins);

/// The band of straight-line elevations (the elevation of the antenna-to-point chord in the
/// site's ENU frame, degrees) that holds every point at chord length r from the antenna whose
/// beam elevation is inside [e_0 - hb, e_{n-1} + hb] (the rule's vertical extent). A beam bends
/// against its straight chord by at most r / (2 R) |1 - 1/ke| rad at chord length r (Doviak &
/// Zrnic 1993, eq. 2.28, to first order in r / R; none for a straight beam); the model's sphere
/// differs from the ellipsoid's normal sections by under 1 %, which moves elevations by under
/// 0.02 deg at 460 km; kStraightElevationBandMarginDeg covers that and float rounding. The one
/// definition of the band: the CPU reference's pre-rejection evaluates it at each point's range,
/// the GPU's ray clipping at the clip radius.
inline constexpr double kStraightElevationBandMarginDeg = 0.1;
struct StraightElevationBand {
  double loDeg = -90.0;  ///< at range 0, margin included
  double hiDeg = 90.0;
  double bendDegPerMeter = 0.0;              ///< widening on each side per metre of range
  double loDegAt(double rangeMeters) const;  ///< clamped to [-90, 90]
  double hiDegAt(double rangeMeters) const;
};
StraightElevationBand straightElevationBand(const PolarVolume& v, bool straightBeam = false);

/// The step rule's cell size of a volume (StepRule.h): the shortest gate spacing, and the finest
/// angle across the beam of the beam width, the sweeps' ray spacing (360 deg / rays) and the gaps
/// between neighbouring sweeps. No sweeps: no rule.
PolarCellScale polarCellScale(const PolarVolume& v);

/// The PolarVolume as a VolumeSampler: exact inverse geolocation (antennaCoordinatesExact) and
/// samplePolar at each point; the ray interval is the clip sphere (clipRadiusMeters around the
/// antenna); provablyEmpty rejects points outside straightElevationBand at their range (points
/// within 1 km of the antenna are never rejected: the chord's elevation is ill-conditioned
/// there). Holds a reference: `volume` must outlive the sampler.
class PolarSampler final : public VolumeSampler {
 public:
  explicit PolarSampler(const PolarVolume& volume, bool rejectOutsideShell = true);
  RayInterval rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const override;
  VolumeSample sample(const glm::dvec3& ecef, Interpolation interpolation) const override;
  bool provablyEmpty(const glm::dvec3& ecef) const override;
  /// The step rule: polarCellCrossingMeters with polarCellScale(polar()).
  double cellCrossingMeters(const glm::dvec3& ecef, const glm::dvec3& unitDirEcef) const override;
  ValueRange valueRange() const override;
  BoundingSphere boundingSphere() const override;  ///< the clip sphere around the antenna
  std::string description() const override;
  const PolarVolume& polar() const { return volume_; }
  const glm::dvec3& antennaEcef() const { return antennaEcef_; }

 private:
  const PolarVolume& volume_;
  glm::dvec3 antennaEcef_{0.0};
  glm::dvec3 upEcef_{0.0};
  StraightElevationBand band_;
  PolarCellScale cellScale_;
  bool reject_ = false;
};

/// The empty-space grid of a PolarVolume, in the site's ENU frame, 256 x 256 x 32 cells over the
/// measured gates' support. Built per block of 2 rays x 4 gates of each sweep: the block's value
/// support under the linear rule (its gates +-1, its rays +-1, from the sweep below to the sweep
/// above, +- half a beam at the ends) is bounded by the box of 27 points on it (the local-sphere
/// beam model, LocalSphereBeam::enuOf), dilated by the support's largest bulge between them.
/// The empty-space grid of the volume as drawn with a vertical exaggeration `factor` (1: true
/// scale): every support box's sample points are exaggerated on the local sphere and the box's
/// margin grows by the factor.
OccupancyGrid buildOccupancyGrid(const PolarVolume& v, double exaggeration = 1.0);

/// Bytes a Cartesian grid would need to hold this volume at the radar's near-range
/// resolution (the finest gate spacing, in x, y and z, over the box enclosing maxRange and
/// the top beam's height), at `bytesPerVoxel`: what resampling to a box would cost (render --stats).
double cartesianEquivalentBytes(const PolarVolume& v, double bytesPerVoxel);

}  // namespace atmoglobe::volume
