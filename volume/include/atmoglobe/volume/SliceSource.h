#pragma once
// A volume loaded for slicing (Slice.h): a radar file (through loadRadar, RadarLoad.h) or one
// variable at one time of a forecast grid (through readGridVolume, GridReader.h), with its
// sampler and what a slice plot says about it (name, field, units, valid time, SYNTHETIC).
// GL-free; `atmoglobe slice` and the scene's slices (engine) both start here.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarVolume.h>
#include <atmoglobe/volume/Slice.h>
#include <atmoglobe/volume/TransferFunction.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace atmoglobe::volume {

struct SliceSourceOptions {
  enum class Kind { Radar, Grid };
  Kind kind = Kind::Radar;
  std::string path;
  std::string field;     ///< radar field or grid variable; empty: the file's default
  std::string time;      ///< grids: "" (first step), an index ("3") or an ISO 8601 UTC time
  bool useGeoid = true;  ///< heights above sea level in the file -> ellipsoid through EGM96
  long member = -1;      ///< grids: the ensemble member (GRIB `number`); -1: the first
  /// Grids: the index along each dimension that is neither horizontal, vertical nor time.
  std::map<std::string, std::size_t> gridIndex;
  /// Grids: a statistic over every member instead of one (GridReadOptions::ensemble).
  std::optional<EnsembleStatistic> ensemble;
  /// Grids: keep each value's pressure on terrain-following levels (GridReadOptions::keepPressure),
  /// for isobaric sections of hybrid, sigma and WRF grids.
  bool keepPressure = false;
};

class SliceSource {
 public:
  /// Reads the file (only the field or variable and time step asked for). Errors: the reader's
  /// (naming the file), a grid variable without any valid value at that time.
  static Result<std::unique_ptr<SliceSource>> load(const SliceSourceOptions& options);

  const VolumeSampler& sampler() const { return *sampler_; }
  const std::string& path() const { return path_; }
  bool isRadar() const { return polar_.has_value(); }
  const PolarVolume* polar() const { return polar_ ? &*polar_ : nullptr; }
  const GridVolume* grid() const { return grid_ ? &*grid_ : nullptr; }

  /// Radar: the site id ("KTLX"; the file name when the file gives none); grid: the file name.
  const std::string& name() const { return name_; }
  const FieldInfo& field() const { return field_; }
  /// Radar: the volume start time; grid: the valid time of the step read (ISO 8601 UTC; "" if
  /// the file has none).
  const std::string& validTime() const { return validTime_; }
  /// True when the file says it is synthetic (SYNTHETIC in its global title, source or comment
  /// attribute: what `atmoglobe synth` writes).
  bool synthetic() const { return synthetic_; }
  /// The box the data can cover (polarExtent / gridExtent).
  const LatLonBox& extent() const { return extent_; }
  /// Heights (m above the WGS84 ellipsoid) between which the volume can have data: a radar's
  /// antenna to the top beam's upper edge at the largest range (4/3-Earth model); a grid's
  /// lowest and highest level.
  double minHeightMeters() const { return minHeight_; }
  double maxHeightMeters() const { return maxHeight_; }
  /// Range of the echo values and the radar's Nyquist velocity (NaN for grids and when unknown).
  ValueRange valueRange() const { return sampler_->valueRange(); }
  double nyquistMps() const { return nyquist_; }
  /// One line for messages and titles: "KTLX (radar)", "synthetic_grid.nc (grid, heights ...)".
  std::string description() const;
  /// The transfer function (its colour table is what the slice and the 3-D view draw) for a
  /// colour choice ("auto", "NWS", "viridis", a .pal file... as transferForField), over `range`
  /// when it is given (min < max), else over the field's own range.
  Result<TransferFunction> transfer(const std::string& colors, const std::optional<ValueRange>& range = {}) const;

 private:
  SliceSource() = default;
  std::optional<PolarVolume> polar_;
  std::optional<GridVolume> grid_;
  std::unique_ptr<VolumeSampler> sampler_;
  std::string path_, name_, validTime_;
  FieldInfo field_;
  bool synthetic_ = false;
  LatLonBox extent_;
  double minHeight_ = 0.0, maxHeight_ = 0.0;
  double nyquist_ = 0.0;
};

/// What to cut through a source: a CAPPI (cappi true: heightMeters over box) or a cross-section
/// (path), the datum and the raster size. Defaults come from the source (sliceGeometryFor).
struct SliceRequest {
  bool cappi = true;
  double heightMeters = 3000.0;  ///< CAPPI height above the datum (m)
  /// Set: an isobaric section at this pressure (Pa) instead of a CAPPI at a height (grids on
  /// pressure levels; samplePressureSection).
  std::optional<double> pressurePa;
  std::optional<LatLonBox> box;                   ///< CAPPI box; default: the source's extent
  std::vector<LatLon> path;                       ///< cross-section points (two or more)
  std::optional<double> bottomMeters, topMeters;  ///< cross-section heights; default 0 .. min(volume top, 20 km)
  SliceHeightDatum datum = SliceHeightDatum::SeaLevel;
  int columns = 512, rows = 512;
};

/// The request's geometry over `source` with its defaults filled in. Errors: the geometry's
/// (bad box or path...), the EGM96 grid missing for heights above sea level, a CAPPI height
/// outside the heights where the volume can have data (message gives them, above the datum).
Result<SliceGeometry> sliceGeometryFor(const SliceSource& source, const SliceRequest& request);

/// The values of a grid on pressure levels on the isobaric surface of a geometry made with
/// CappiSpec::pressurePa, at each pixel centre: in each grid column the two levels that bracket
/// the pressure, interpolated linearly in ln(p) (a level's own values where the pressure is a
/// level), then the grid's horizontal interpolation at the pixel (GridSampler::columnsAt, the
/// weights a sample takes). Nearest: the level nearest in ln(p) and the nearest column. A value
/// missing in any column or level used is no data. Errors: a radar, a grid whose levels are not
/// pressure levels, a pressure outside the grid's levels (the message gives them in hPa).
Result<SliceRaster> samplePressureSection(const SliceSource& source, const SliceGeometry& geometry,
                                          Interpolation interpolation = Interpolation::Linear, int threads = 0);
/// The grid's pressure levels in Pa (bottom first), or an error saying why there are none.
Result<std::vector<double>> pressureLevelsPa(const GridVolume& grid);
/// The levels k, k + 1 around a pressure and the weight f of level k + 1, linear in ln(p) (a
/// level's own pressure: f 0 or 1). Errors: pressureLevelsPa's, a pressure outside the levels
/// (the message gives them in hPa).
Result<std::pair<std::size_t, double>> pressureBracket(const GridVolume& grid, double pressurePa);

/// Samples `geometry` through the source's sampler (sampleSlice). Error when no pixel has data:
/// "FILE: no data on the CAPPI at 25 km above sea level (...)" / "... the path does not cross".
Result<SliceRaster> sampleSource(const SliceSource& source, const SliceGeometry& geometry,
                                 Interpolation interpolation = Interpolation::Linear, int threads = 0);

/// Parses "LAT,LON;LAT,LON[;...]" (degrees; blanks allowed). Errors say which point is wrong.
Result<std::vector<LatLon>> parsePathText(const std::string& text);
/// Parses "SOUTH,NORTH,WEST,EAST" (degrees; west > east crosses the antimeridian and is made
/// continuous) and validates it.
Result<LatLonBox> parseBoxText(const std::string& text);

/// True when a netCDF file's global title, source or comment attribute contains "SYNTHETIC".
/// False for anything else (other formats, unreadable files).
bool fileSaysSynthetic(const std::string& path);
/// The overlap rule of a 3-D radar mosaic written by `atmoglobe mosaic` (its global attribute
/// overlap_rule, Mosaic.h), empty for any other file: a grid layer of it is labelled a mosaic.
std::string mosaicOverlapRule(const std::string& path);

}  // namespace atmoglobe::volume
