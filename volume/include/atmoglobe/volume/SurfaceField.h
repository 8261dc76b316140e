#pragma once
// A 2-D field of a forecast grid as a map on the globe: a surface or single-level variable, or a
// 3-D variable on its isobaric surface at a pressure. GL-free: the engine drapes it
// (engine/SurfaceFieldGL.h), this is its CPU reference and the values its contours are drawn from.
//
// The field keeps the grid's own geometry: one value per column (grid point), nx x ny, NaN
// missing. Its value at a latitude/longitude is the grid's horizontal interpolation
// (GridSampler::horizontalIndex and columnsAt: bilinear in the grid's fractional column and row,
// across the seam of a grid that wraps in longitude, the polar caps of a global grid closed by
// the mean of its end rows); a column used that is missing makes the value missing. On an
// isobaric surface each column's value is the level pair around the pressure interpolated
// linearly in ln(p), as `slice --pressure-hpa` does (isobaricColumnValues), so the surface's
// value at a point is the section's there.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/RenderCamera.h>
#include <atmoglobe/volume/VolumeImage.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume {

struct SurfaceField {
  /// The grid's horizontal geometry with nz = 1 and the field's values (ny x nx; heights 0).
  GridVolume grid;
  std::string name;                  ///< "msl", "t at 500 hPa"
  std::optional<double> pressurePa;  ///< set: an isobaric surface of a 3-D variable
};

/// The field of `grid`: its only level (a 2-D variable), or with `pressurePa` its isobaric
/// surface, or with `level` that level (0 = the lowest; a model level of any grid). A geopotential (m2 s-2, or other
/// geopotential units) becomes geopotential height in decametres ("dam"), as `slice` draws it. Errors: several levels
/// and no pressure ("... has 4 levels: give a pressure level"), a pressure on a grid not on pressure levels or outside
/// them, a reduced grid (not drawn as a surface yet), no finite value.
Result<SurfaceField> surfaceFieldOf(GridVolume grid, std::optional<double> pressurePa = std::nullopt,
                                    std::optional<std::size_t> level = std::nullopt);

/// Each column's value on the isobaric surface at `pressurePa` (ny x nx, NaN where a level used
/// is missing): the two levels around the pressure, linear in ln(p) (`nearestLevel`: the nearer
/// in ln(p)). Pressure levels take the grid's levels (pressureBracket); a grid with per-value
/// pressures (GridVolume::pressurePa: hybrid, sigma, WRF eta) takes each column's own, and a
/// column whose levels do not reach the pressure (the surface under ground) has none.
/// Errors: as pressureLevelsPa (SliceSource.h), a pressure outside every column's levels.
Result<std::vector<float>> isobaricColumnValues(const GridVolume& grid, double pressurePa, bool nearestLevel = false);

/// The field's value at a point by the grid's horizontal interpolation (file comment); NaN
/// outside the grid or where a column used is missing. Keeps a reference to the field.
class SurfaceSampler {
 public:
  explicit SurfaceSampler(const SurfaceField& field);
  double valueAt(double latDeg, double lonDeg) const;
  const SurfaceField& field() const { return field_; }

 private:
  const SurfaceField& field_;
  std::unique_ptr<GridSampler> sampler_;
};

/// Whether a value shows under a colour table (finite and at or above its first stop; the
/// table's alpha is a volume's opacity per length and is not used by a surface).
bool surfaceValueShows(const ColorTable& table, double value);

/// The CPU reference of a draped field: each pixel's ray meets the WGS84 ellipsoid exactly
/// (globe::intersectRayEllipsoid, the nearer hit), the point's geodetic latitude and longitude
/// (GeographicLib) give the value (SurfaceSampler), the table its colour (RGB of
/// ColorTable::map), drawn with `opacity` where surfaceValueShows; premultiplied, over nothing.
VolumeImage renderSurfaceReference(const SurfaceSampler& sampler, const ColorTable& table, double opacity,
                                   const RenderCamera& camera);

}  // namespace atmoglobe::volume
