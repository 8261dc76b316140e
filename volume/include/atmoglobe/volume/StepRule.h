#pragma once
// Samples where the data need them: the step along a ray follows the size of the cells the ray
// crosses there (docs/volume-rendering.md, "The step rule"). The GPU marcher (volume_march.frag)
// and the CPU reference (ReferenceRenderer) follow this rule alike; the GPU's copy of
// cellCrossingMeters is VOL_cellCrossing in the kind's shader.
//
// Samples sit on the fine grid t_i = (i + 0.5) step of the fixed-step march. Each sample has a
// level L (0 .. kMaxStepLevel): it stands for a step of 2^L fine steps, and the next sample is
// the next fine index that is a multiple of 2^L' where L' is the level found there:
//   L(c) = the smallest of stepLevel(cellCrossingMeters at t_c, step, samplesPerCell) over the
//          volumes whose range holds c (no volume there, or a kind without a rule: 0) and of
//          stepLevel(t_c / focalPx, step, 1): never more than the footprint of a pixel of the
//          full-resolution image at that distance, so that the positions' pattern (the edges and
//          bands a coarse step draws) stays below a pixel on the screen,
//   start: c = the first index, L = L(c), i = alignUp(c, L);
//   next:  c = i + 2^L,         L = L(c), i = alignUp(c, L).
// Positions depend on the geometry only (no sample value), so skipping empty space lands where
// the walk would wherever the level is the same on both sides of the jump (the jump's target is
// aligned by the same rule), and positions in a region of one level are its multiples of 2^L.
// samplesPerCell = 0 is the fixed step (every L is 0).
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace atmoglobe::volume {

/// Largest step level: 2^7 = 128 fine steps (32 km at the 250 m default).
inline constexpr int kMaxStepLevel = 7;

/// A volume's cell size as the step rule reads it. Values are rounded to float, as the GPU holds
/// them, so that both evaluate the same table.
struct CellScale {
  double columnSpacingMeters = 0.0;  ///< horizontal distance between neighbouring columns (m)
  double minHeightMeters = 0.0;      ///< the table's first entry starts here
  double entriesPerMeter = 0.0;      ///< entry of height h: floor((h - min) x this), clamped
  /// kEntries values: the smallest spacing of the reference levels (mean level heights) that
  /// overlap each entry's heights (m); empty: no rule (fixed step).
  std::vector<double> levelSpacingMeters;
  static constexpr int kEntries = 32;
};

/// A radar volume's cell size as the step rule reads it (polarCellScale in PolarVolume.h builds
/// it). Rounded to float, as the GPU holds them.
struct PolarCellScale {
  double gateMeters = 0.0;  ///< the shortest gate spacing of the sweeps (m); 0: no rule
  /// The finest angle across the beam (rad): the smallest of the beam width, the sweeps' ray
  /// spacing (360 deg / rays) and the gaps between neighbouring sweep elevations.
  double acrossRad = 0.0;
};

/// The length of ray that crosses one radar cell at `fromAntenna` (ECEF offset of the point from
/// the antenna, m) going along `unitDir`: with r = |fromAntenna| and cos the angle between the ray
/// and the line from the antenna (the beam taken straight: the 4/3 beam's tangent leaves that
/// line by at most r / (2R) |1 - 1/ke|, 0.56 deg at 500 km, where a level is a power of two), the smaller of the gate
/// spacing over |cos| and the beam's width there, r x acrossRad, over sin. 0 when the scale has no rule or the point is
/// at the antenna.
double polarCellCrossingMeters(const PolarCellScale& scale, const glm::dvec3& fromAntenna, const glm::dvec3& unitDir);

/// Height above the WGS84 ellipsoid of an ECEF point, approximated as its distance from the
/// centre less the ellipse's radius at its geocentric latitude (within metres of the geodetic
/// height in the atmosphere; a rule for the step, not a geolocation).
double approximateHeightMeters(const glm::dvec3& ecef);

/// The length of ray that crosses one cell at `ecef` going along `unitDir`: the smaller of the
/// level spacing there over |cos| of the ray's angle with the local vertical (the geocentric
/// direction) and the column spacing over |sin| of it. 0 when the scale has no table.
double cellCrossingMeters(const CellScale& scale, const glm::dvec3& ecef, const glm::dvec3& unitDir);

/// The step level of a crossing: floor(log2(crossing / (samplesPerCell x step))) clamped to
/// [0, kMaxStepLevel]; 0 when samplesPerCell <= 0 or crossing <= 0.
int stepLevel(double crossingMeters, double stepMeters, double samplesPerCell);

/// c rounded up to a multiple of 2^level.
inline std::int64_t alignUp(std::int64_t c, int level) {
  const std::int64_t m = (std::int64_t{1} << level) - 1;
  return (c + m) & ~m;
}

/// The table of CellScale from level heights (m) ordered bottom to top: each level's mean over
/// the columns, made non-decreasing; `minHeightMeters`, `maxHeightMeters`: the table's domain.
CellScale cellScaleFromLevels(const std::vector<double>& meanLevelHeightsMeters, double minHeightMeters,
                              double maxHeightMeters, double columnSpacingMeters);

}  // namespace atmoglobe::volume
