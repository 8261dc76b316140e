#pragma once
// Any volume (radar or grid) resampled onto a regular grid and written as NRRD (the format of
// teem, 3D Slicer, ParaView and VisIt), for users who want the data in another tool.
//
// The resampling goes through the volume's VolumeSampler in double: the same sampling rule the
// CPU reference renderer uses, so an exported value is what the reference would see there.
// Two kinds of regular grid:
//   - geographic: longitude x latitude x height (node-centred samples from the first to the last
//     value of each axis), heights above mean sea level (EGM96) or above the WGS84 ellipsoid;
//   - local Cartesian: x east, y north, z up (m) in the tangent plane at a centre point on the
//     ellipsoid (z is along the ellipsoid normal at the centre, not a height).
// Values are float; no data and no echo are both written as NaN (NRRD has one value per sample;
// the header says so in its key/value pairs).
//
// Header (NRRD0004): type, dimension, sizes, encoding (gzip or raw), endian, content; the
// geographic kind gives per-axis labels, units, kinds and axis mins / maxs / spacings; the
// Cartesian kind a 3-D space with space units, space origin and space directions (in the local
// frame). Key/value pairs: the value units, the source file, the field, the valid time, the
// datum and the frame's centre. Written atomically (AtomicFile.h).
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/RadarVolume.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace atmoglobe::volume {

struct GridVolume;
struct PolarVolume;
class GeoidGrid;

enum class RegularGridKind { Geographic, LocalCartesian };

struct RegularGridSpec {
  RegularGridKind kind = RegularGridKind::Geographic;
  std::size_t nx = 0, ny = 0, nz = 0;  ///< samples along x (longitude / east), y, z
  // Geographic: the first and last sample of each axis. eastDeg > westDeg (longitudes are
  // continuous: a box across the antimeridian runs e.g. from 170 to 190).
  double westDeg = 0.0, eastDeg = 0.0, southDeg = 0.0, northDeg = 0.0;
  double bottomMeters = 0.0, topMeters = 0.0;  ///< heights above `datum`
  HeightDatum datum = HeightDatum::MeanSeaLevel;
  // LocalCartesian: the tangent plane at (centerLatDeg, centerLonDeg, ellipsoid height 0);
  // first and last sample of each axis in metres.
  double centerLatDeg = 0.0, centerLonDeg = 0.0;
  double xMinMeters = 0.0, xMaxMeters = 0.0, yMinMeters = 0.0, yMaxMeters = 0.0;
  double zMinMeters = 0.0, zMaxMeters = 0.0;

  std::size_t sampleCount() const { return nx * ny * nz; }
};

/// Checks a spec: sizes >= 1 (and >= 2 where first != last), finite ranges in order, latitudes
/// within [-90, 90], a longitude span of at most 360 deg, at most `maxSamples` samples.
Status validateRegularGridSpec(const RegularGridSpec& spec, std::size_t maxSamples);

/// The default geographic grid of a forecast grid: its own columns and rows (rectilinear:
/// the first/last longitude and latitude; curvilinear: the bounding box at the grid's mean
/// spacing), heights from the lowest to the highest level centre at `levelSpacingMeters`.
RegularGridSpec defaultRegularGrid(const GridVolume& grid, HeightDatum datum, const GeoidGrid* geoid,
                                   double levelSpacingMeters = 250.0);
/// The default geographic grid of a radar: a box of +-maxRange around the site at
/// `horizontalSpacingMeters`, heights from the lowest to the highest gate centre at
/// `levelSpacingMeters`.
RegularGridSpec defaultRegularGrid(const PolarVolume& radar, HeightDatum datum, const GeoidGrid* geoid,
                                   double horizontalSpacingMeters = 1000.0, double levelSpacingMeters = 250.0);

/// Samples `sampler` at every node of `spec` (x fastest, then y, then z), NaN where it has no
/// data or no echo. `geoid` is required when spec.datum is SeaLevel for a geographic grid.
/// Threads split the z levels.
Result<std::vector<float>> resampleRegular(const VolumeSampler& sampler, const RegularGridSpec& spec,
                                           Interpolation interpolation, const GeoidGrid* geoid, unsigned threads = 0,
                                           const std::function<void(std::size_t, std::size_t)>& levelDone = {});

struct NrrdMetadata {
  std::string content;     ///< one line: what the values are ("QCLOUD (kg kg-1) ...")
  std::string valueUnits;  ///< units of the values ("dBZ", "K")
  /// Extra key/value pairs (written as "key:=value"; newlines are replaced by spaces).
  std::vector<std::pair<std::string, std::string>> keyValues;
};

/// The NRRD header text of `spec` (up to and including the blank line that ends it).
std::string nrrdHeader(const RegularGridSpec& spec, const NrrdMetadata& meta, bool gzip);

/// Writes header + values (spec.sampleCount() floats, little-endian; gzip-compressed when
/// `gzip`) to `path` atomically.
Status writeNrrd(const std::string& path, const RegularGridSpec& spec, const std::vector<float>& values,
                 const NrrdMetadata& meta, bool gzip = true);

/// `atmoglobe convert`: one radar field or grid variable at one time, resampled and written.
struct NrrdExportOptions {
  std::string inputPath;   ///< radar file or forecast grid (decided from the content)
  std::string outputPath;  ///< .nrrd; empty: nothing written, the values returned (NrrdExportReport::values)
  std::string variable;    ///< grid variable or radar field; empty: the default one
  std::string time;        ///< grids: an index or an ISO 8601 time (selectGridTime); empty: the first
  long member = -1;        ///< grids: the ensemble member (GRIB `number`); -1: the first
  std::optional<EnsembleStatistic> ensemble;  ///< grids: a statistic over every member instead
  /// Grids: the index along each dimension that is neither horizontal, vertical nor time.
  std::map<std::string, std::size_t> gridIndex;
  /// Box SOUTH, NORTH, WEST, EAST (deg; west > east crosses the antimeridian): grids read only
  /// this box; the regular grid spans it.
  std::optional<std::array<double, 4>> cropSouthNorthWestEastDeg;
  /// Heights BOTTOM, TOP (m above `datum`; Cartesian: z range) of the regular grid.
  std::optional<std::array<double, 2>> heightRangeMeters;
  std::optional<std::array<std::size_t, 3>> size;  ///< NX, NY, NZ; default: the data's own spacing
  RegularGridKind kind = RegularGridKind::Geographic;
  HeightDatum datum = HeightDatum::MeanSeaLevel;
  Interpolation interpolation = Interpolation::Linear;
  bool useGeoid = true;  ///< as the readers (antenna / model heights above sea level)
  bool gzip = true;
  /// Refused above this many samples (4 bytes each in memory, before compression).
  std::size_t maxSamples = std::size_t{1} << 29;
  unsigned threads = 0;  ///< 0: all hardware threads
  /// Optional: called (from worker threads, in any order) after each height level is resampled,
  /// with (levels done, levels): `atmoglobe convert`'s progress.
  std::function<void(std::size_t, std::size_t)> progress;
};

struct NrrdExportReport {
  RegularGridSpec spec;
  std::string kindText;  ///< "forecast grid" or "radar volume"
  std::string field;     ///< the variable or field written
  std::string units;
  std::string validTime;            ///< ISO 8601 UTC ("" if unknown)
  std::uint64_t bytesRead = 0;      ///< grids: the reader's bytesRead
  std::size_t finiteValues = 0;     ///< samples with a value (not NaN)
  bool approximateHeights = false;  ///< grids: heights estimated (standard atmosphere...)
  std::string heightNote;           ///< grids: how heights were derived
  /// The resampled values (x fastest, then y, then z) when no output path was given.
  std::vector<float> values;
};

/// Reads, resamples and writes. Errors name the file and the problem (bad spec, unreadable
/// input, no such variable, too many samples); the previous output is kept on any error.
Result<NrrdExportReport> exportNrrd(const NrrdExportOptions& options);

}  // namespace atmoglobe::volume
