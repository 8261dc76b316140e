#pragma once
// A forecast grid (GridVolume.h) as a volume kind: the CPU sampler the reference renderer draws
// it through, in double precision, in the grid's own geometry (no Cartesian resampling).
//
// The sampling rule (the GPU's sampler implements the same):
//  1. the ECEF point to geodetic latitude, longitude, height above the WGS84 ellipsoid
//     (GeographicLib, exact);
//  2. horizontal grid coordinates (fractional column i, row j; integer = a grid point):
//     rectilinear: by search in the 1-D longitudes (the longitude taken modulo 360 into the
//     grid's continuous range) and latitudes, linear between neighbours; a grid that wraps in
//     longitude interpolates between its last and first column across the seam; a global grid
//     (wrapsLongitude) closes its polar caps: beyond its last row the columns blend linearly in
//     latitude into one value at the pole, the mean of that row (per level, heights too), so the
//     cap has neither a hole nor a seam. Curvilinear: the cell holding the point (a bin index
//     over the cells' latitude/longitude boxes) and the bilinear inverse of its four corners by
//     Newton's method to 1e-10 of a cell: exact to rounding. Latitudes and longitudes as given,
//     except for a grid reaching beyond 80 degrees of latitude or spanning more than 180 degrees
//     of longitude (a polar stereographic grid around a pole): there in a chart, the sphere turned
//     so that the grid's mean direction lies at latitude 0, longitude 0, where its longitudes run
//     continuously (the pole becomes an ordinary point between grid points). Reduced (rows of
//     different lengths, GridVolume.h): the rows j0, j0 + 1 around the latitude as for a
//     rectilinear grid (polar caps included), and in each row its own fractional column from the
//     longitude, (longitude - the row's first longitude, modulo 360) / the row's spacing, across
//     the seam from its last point to its first when the grid wraps; a row of positive weight not
//     holding the longitude (a regional grid): outside. The i of (i, j) is the longitude on the
//     grid's reference axis, (longitude - reducedWestDeg(), modulo 360) / reducedSpacingDeg(): the
//     fractional column in units of the finest row spacing (the longest row's for a global grid),
//     what the GPU's mapping is measured against; each row's column follows from it;
//  3. the columns around (i, j) with bilinear weights (1, 2 or 4 of them; reduced: two in each
//     row, weighted by that row's own column fraction, then linear in latitude between the
//     rows); level k's height at
//     the point is the weighted mean of theirs (monotonic, as each column is); the fractional
//     level is found by bisection in these heights; below the lowest level's height or above the
//     highest: no data;
//  4. linear: the value at level k is the weighted mean of the columns' values, and the sample
//     is linear in height between levels k and k + 1 (heights come from the reader; for pressure
//     levels a layer's height is, hydrostatically, linear in log pressure for an isothermal layer,
//     so this is interpolation linear in log pressure to that approximation). Nearest: the
//     column of largest weight and the nearer level. Any needed value missing (NaN): no data.
// A grid has no "no echo": every finite value is a sample; the transfer function decides what
// shows.
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/OccupancyGrid.h>
#include <atmoglobe/volume/StepRule.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume {

/// The columns around a horizontal position and their weights (sum 1). A column index >= 0 is
/// j * nx + i; kNorthPole / kSouthPole are a global grid's virtual pole columns.
struct GridColumns {
  static constexpr int kNorthPole = -1, kSouthPole = -2;
  /// A closed column beyond a reduced grid's row (closedColumn): padding, no grid point (NaN).
  static constexpr int kPadding = -3;
  std::array<int, 4> column{};
  std::array<double, 4> weight{};
  int count = 0;
};

/// Nearest-neighbour sampling's column: the one of largest weight, with weight 1 (unchanged when
/// there is none).
GridColumns heaviestColumn(GridColumns columns);

class GridSampler final : public VolumeSampler {
 public:
  /// Keeps a reference to `grid` (must outlive the sampler). Builds the curvilinear cell index
  /// and, for global grids, the pole columns.
  explicit GridSampler(const GridVolume& grid);

  RayInterval rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const override;
  VolumeSample sample(const glm::dvec3& ecef, Interpolation interpolation) const override;
  BoundingSphere boundingSphere() const override { return sphere_; }
  /// The step rule (StepRule.h) with cellScale().
  double cellCrossingMeters(const glm::dvec3& ecef, const glm::dvec3& unitDirEcef) const override;
  /// The grid's cell size for the step rule: its mean level heights' spacing by height and the
  /// distance between neighbouring columns at its middle grid point.
  const CellScale& cellScale() const { return cellScale_; }
  ValueRange valueRange() const override;
  std::string description() const override;

  /// Step 2: fractional (column i, row j) of a geodetic position; nullopt outside the grid
  /// horizontally. For a global grid's polar cap, j runs past the last row (ny - 1 + t, t the
  /// fraction of the way to the pole) or below 0 (-t).
  std::optional<glm::dvec2> horizontalIndex(double latDeg, double lonDeg) const;
  /// Step 3's columns and weights for a fractional (i, j) from horizontalIndex.
  GridColumns columnsAt(const glm::dvec2& ij) const;
  /// Step 2's fractional row j of a latitude (rectilinear and reduced grids, polar caps
  /// included); nullopt outside the rows (and for curvilinear grids).
  std::optional<double> rowIndex(double latDeg) const;
  /// The sample at a geodetic position (steps 2-4), as sample() after its step 1.
  VolumeSample sampleGeodetic(double latDeg, double lonDeg, double heightMeters, Interpolation interpolation) const;
  /// Fractional (column i, row j, level k) of a geodetic position by steps 2-3 (linear weights);
  /// nullopt where sample() gives no data for lack of a position (outside horizontally, below
  /// the lowest or above the highest level there). What the GPU's mapping is measured against.
  std::optional<glm::dvec3> gridIndex(double latDeg, double lonDeg, double heightMeters) const;
  /// The grid sampled.
  const GridVolume& grid() const { return grid_; }
  /// Lowest and highest height of any level (m above the ellipsoid).
  double minHeightMeters() const { return minHeight_; }
  double maxHeightMeters() const { return maxHeight_; }

  /// Level k's height and value in a column of GridColumns (a pole column: the end row's mean;
  /// its value NaN when any of the row's is missing).
  double columnHeight(int column, std::size_t k) const;
  float columnValue(int column, std::size_t k) const;
  /// Whether a global grid's polar caps are closed by pole columns.
  bool hasPoleCaps() const { return poleCaps_; }

  /// The grid closed as the marcher samples it (and the GPU's textures hold it): x columns = nx,
  /// + 1 (a copy of column 0) when a rectilinear grid wraps in longitude; y rows = ny, + 2 (a pole
  /// row below the first and above the last) with pole caps; z levels = nz. A reduced grid: x =
  /// nx + 1 when it wraps, row j closed by a copy of its column 0 after its last point (closed
  /// column rowLength(j)), the columns beyond padding (kPadding).
  glm::ivec3 closedSize() const;
  /// The closed row holding grid row 0: 1 with pole caps, else 0.
  int closedRowOffset() const { return poleCaps_ ? 1 : 0; }
  /// The GridColumns column of closed column tc, row tr: a grid column, column 0 again or a pole.
  int closedColumn(int tc, int tr) const;
  /// The column whose level heights closed column tc, row tr holds on the GPU: closedColumn, and
  /// for a reduced row's padding the row's last closed column (finite heights where the shader
  /// may fetch with weight 0).
  int closedHeightColumn(int tc, int tr) const;
  /// Latitude, longitude (degrees) of closed column tc, row tr: the copy of column 0 at its
  /// longitude + 360, a pole at the longitude of grid column 0.
  glm::dvec2 closedLatLonDeg(int tc, int tr) const;
  /// A reduced grid's closed row tr, as the GPU's row table holds it: its closed columns (the
  /// row's points, + 1 for the copy of its first when the grid wraps; a pole row: 2, both the
  /// pole), the longitude of its column 0 and its spacing (a pole row: reducedWestDeg(), 360).
  struct ClosedRow {
    int columns = 0;
    double firstLonDeg = 0.0, spacingDeg = 360.0;
  };
  ClosedRow closedRow(int tr) const;
  /// A reduced grid's reference axis (GridVolume::reducedWestDeg, reducedSpacingDeg): the i of
  /// horizontalIndex is (longitude - west, modulo 360) / spacing. 0 and 1 for other grids.
  double reducedWestDeg() const { return west_; }
  double reducedSpacingDeg() const { return step_; }

 private:
  /// Step 3's level: lo + f by bisection in the columns' blended heights; nullopt below the
  /// lowest or above the highest level there.
  std::optional<double> fractionalLevel(const GridColumns& columns, double heightMeters) const;
  std::optional<glm::dvec2> curvilinearIndex(double latDeg, double lonDeg) const;
  /// A latitude/longitude in the chart (step 2): (longitude, latitude) there, degrees.
  glm::dvec2 toChart(double latDeg, double lonDeg) const;
  /// The rows around a fractional row j and their weights (a pole: kNorthPole / kSouthPole).
  struct RowWeight {
    int row;
    double weight;
  };
  std::array<RowWeight, 2> rowsAt(double j) const;
  /// A reduced grid's fractional column of a longitude in row j (0 .. rowLength, past rowLength
  /// - 1 across the seam of a wrapping grid); nullopt when the row does not hold it.
  std::optional<double> rowColumn(std::size_t j, double lonDeg) const;

  const GridVolume& grid_;
  double minHeight_ = 0.0, maxHeight_ = 0.0;
  CellScale cellScale_;
  BoundingSphere sphere_;
  // Global grids: the pole columns (per level: mean height, mean value of the end row; NaN
  // value if any value of the row is missing).
  bool poleCaps_ = false;
  std::vector<double> northHeight_, southHeight_;
  std::vector<float> northValue_, southValue_;
  // Reduced: the reference axis of the column index i.
  double west_ = 0.0, step_ = 1.0;
  // Curvilinear: longitudes continuous from lonMin_, and a uniform bin index over latitude and
  // longitude listing the cells (j * (nx - 1) + i) whose corner box overlaps each bin.
  double lonMin_ = 0.0, latMinBin_ = 0.0, lonMinBin_ = 0.0, binLatDeg_ = 1.0, binLonDeg_ = 1.0;
  int binsLat_ = 0, binsLon_ = 0;
  std::vector<std::vector<std::uint32_t>> bins_;
  // Curvilinear grids near a pole or wider than 180 degrees: the chart's rotation (rows: the
  // chart's x, y, z axes in ECEF directions) and every point's chart latitude and longitude.
  bool charted_ = false;
  glm::dmat3 chart_{1.0};
  std::vector<double> chartLat_, chartLon_;
};

/// The grid's empty-space grid (OccupancyGrid.h), 128 x 128 x 32 cells in the local frame of its
/// bounding sphere's centre (ENU there; ECEF axes for a global grid, whose sphere is centred on
/// the Earth's): a box per block of 8 x 8 closed columns x 4 levels holding every point of the
/// block and of its far neighbours (samples interpolate up to the next column and level), with
/// the block's largest value. The box is widened by the sagitta of its width over a 6350 km
/// Earth (the levels curve between the columns), 5 % of the width and 10 m. Heights are taken
/// as the GPU holds them (float). A reduced grid's blocks are 8 closed rows x 8 reference
/// columns (reducedSpacingDeg) of longitude x 4 levels: the box holds that latitude/longitude
/// region between the lowest height at its bottom level and the highest at its top level of
/// every column a sample in it interpolates (in each row, those whose cells meet the block's
/// longitudes), and their largest value.
OccupancyGrid buildOccupancyGrid(const GridSampler& s);

}  // namespace atmoglobe::volume
