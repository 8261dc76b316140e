#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/ParallelFor.h>
#include <atmoglobe/volume/AtomicFile.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/NrrdExport.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarLoad.h>

#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>

namespace atmoglobe::volume {

namespace {
const char* datumText(HeightDatum d) {
  return d == HeightDatum::MeanSeaLevel ? "mean sea level (EGM96)" : "WGS84 ellipsoid";
}
}  // namespace

namespace {

bool finiteAll(std::initializer_list<double> values) {
  for (double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

// Step between node-centred samples (0 for a single sample).
double axisStep(double first, double last, std::size_t n) {
  return n > 1 ? (last - first) / static_cast<double>(n - 1) : 0.0;
}

std::string formatNumber(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

std::string oneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  return text;
}

}  // namespace

Status validateRegularGridSpec(const RegularGridSpec& spec, std::size_t maxSamples) {
  if (spec.nx == 0 || spec.ny == 0 || spec.nz == 0) return makeError("every axis needs at least one sample");
  const double total = static_cast<double>(spec.nx) * static_cast<double>(spec.ny) * static_cast<double>(spec.nz);
  if (total > static_cast<double>(maxSamples)) {
    return makeError("the grid has " + std::to_string(spec.nx) + " x " + std::to_string(spec.ny) + " x " +
                     std::to_string(spec.nz) + " samples, more than the limit of " + std::to_string(maxSamples) +
                     " (choose a smaller size)");
  }
  auto axis = [](double first, double last, std::size_t n, const char* name) -> Status {
    if (last < first) return makeError(std::string(name).append(" range runs backwards"));
    if (n > 1 && last == first) return makeError(std::string(name).append(" range is empty but has several samples"));
    return Ok{};
  };
  if (spec.kind == RegularGridKind::Geographic) {
    if (!finiteAll({spec.westDeg, spec.eastDeg, spec.southDeg, spec.northDeg, spec.bottomMeters, spec.topMeters}))
      return makeError("the grid's ranges must be finite");
    if (spec.southDeg < -90.0 || spec.northDeg > 90.0) return makeError("latitudes must lie within [-90, 90]");
    if (spec.eastDeg - spec.westDeg > 360.0) return makeError("the longitude span exceeds 360 deg");
    if (auto st = axis(spec.westDeg, spec.eastDeg, spec.nx, "longitude"); !st) return st;
    if (auto st = axis(spec.southDeg, spec.northDeg, spec.ny, "latitude"); !st) return st;
    if (auto st = axis(spec.bottomMeters, spec.topMeters, spec.nz, "height"); !st) return st;
  } else {
    if (!finiteAll({spec.centerLatDeg, spec.centerLonDeg, spec.xMinMeters, spec.xMaxMeters, spec.yMinMeters,
                    spec.yMaxMeters, spec.zMinMeters, spec.zMaxMeters}))
      return makeError("the grid's ranges must be finite");
    if (std::abs(spec.centerLatDeg) > 90.0) return makeError("the centre latitude must lie within [-90, 90]");
    if (auto st = axis(spec.xMinMeters, spec.xMaxMeters, spec.nx, "x"); !st) return st;
    if (auto st = axis(spec.yMinMeters, spec.yMaxMeters, spec.ny, "y"); !st) return st;
    if (auto st = axis(spec.zMinMeters, spec.zMaxMeters, spec.nz, "z"); !st) return st;
  }
  return Ok{};
}

namespace {

// Heights of a regular grid's z axis from the lowest to the highest level centre of a forecast
// grid (in `datum`), and the count at `spacing`.
void fitHeights(double lowEllipsoid, double highEllipsoid, double undulationLow, double undulationHigh,
                HeightDatum datum, double spacingMeters, RegularGridSpec& spec) {
  double bottom = lowEllipsoid, top = highEllipsoid;
  if (datum == HeightDatum::MeanSeaLevel) {
    bottom -= undulationLow;
    top -= undulationHigh;
  }
  spec.bottomMeters = std::floor(bottom / spacingMeters) * spacingMeters;
  spec.topMeters = std::max(spec.bottomMeters + spacingMeters, std::ceil(top / spacingMeters) * spacingMeters);
  spec.nz = static_cast<std::size_t>(std::llround((spec.topMeters - spec.bottomMeters) / spacingMeters)) + 1;
}

}  // namespace

RegularGridSpec defaultRegularGrid(const GridVolume& grid, HeightDatum datum, const GeoidGrid* geoid,
                                   double levelSpacingMeters) {
  RegularGridSpec spec;
  spec.kind = RegularGridKind::Geographic;
  spec.datum = datum;
  if (!grid.curvilinear) {
    spec.westDeg = grid.lonDeg.front();
    spec.eastDeg = grid.reduced() ? grid.reducedEastDeg() : grid.lonDeg.back();  // reduced: lonDeg is its axis
    spec.southDeg = grid.latDeg.front();
    spec.northDeg = grid.latDeg.back();
    spec.nx = grid.nx;
    spec.ny = grid.ny;
  } else {
    // Bounding box of the columns in continuous longitudes about the grid's centre column.
    const double lonRef = grid.lonDegAt(grid.ny / 2, grid.nx / 2);
    double west = 1e9, east = -1e9, south = 90.0, north = -90.0;
    for (std::size_t j = 0; j < grid.ny; ++j) {
      for (std::size_t i = 0; i < grid.nx; ++i) {
        const double lon = lonRef + globe::wrapLongitudeDeg(grid.lonDegAt(j, i) - lonRef);
        west = std::min(west, lon);
        east = std::max(east, lon);
        south = std::min(south, grid.latDegAt(j, i));
        north = std::max(north, grid.latDegAt(j, i));
      }
    }
    spec.westDeg = west;
    spec.eastDeg = east;
    spec.southDeg = south;
    spec.northDeg = north;
    // As many samples as the grid has columns and rows: the same mean spacing.
    spec.nx = grid.nx;
    spec.ny = grid.ny;
  }
  float low = std::numeric_limits<float>::max(), high = std::numeric_limits<float>::lowest();
  const std::size_t columns = grid.nx * grid.ny;
  for (std::size_t c = 0; c < columns; ++c) {
    if (!std::isfinite(grid.heightAboveEllipsoidMeters[c])) continue;  // a reduced grid's padding
    low = std::min(low, grid.heightAboveEllipsoidMeters[c]);
    high = std::max(high, grid.heightAboveEllipsoidMeters[(grid.nz - 1) * columns + c]);
  }
  // The undulation at the grid's centre: the default height range is a convenience, its ends
  // rounded to the spacing, so one undulation (|N| < 110 m) for the whole box is enough here.
  const double n = (datum == HeightDatum::MeanSeaLevel && geoid)
                       ? geoid->undulationMeters(0.5 * (spec.southDeg + spec.northDeg),
                                                 globe::wrapLongitudeDeg(0.5 * (spec.westDeg + spec.eastDeg)))
                       : 0.0;
  fitHeights(low, high, n, n, datum, levelSpacingMeters, spec);
  return spec;
}

RegularGridSpec defaultRegularGrid(const PolarVolume& radar, HeightDatum datum, const GeoidGrid* geoid,
                                   double horizontalSpacingMeters, double levelSpacingMeters) {
  RegularGridSpec spec;
  spec.kind = RegularGridKind::Geographic;
  spec.datum = datum;
  const double lat = radar.site.latDeg;
  const double range = radar.maxRangeMeters;
  // Degrees per metre along the meridian and the parallel at the site (WGS84 radii of curvature).
  const double s = std::sin(degreesToRadians(lat));
  const double w = std::sqrt(1.0 - globe::kWgs84E2 * s * s);
  const double meridianRadius = globe::kWgs84A * (1.0 - globe::kWgs84E2) / (w * w * w);
  const double primeRadius = globe::kWgs84A / w;
  const double dLat = radiansToDegrees(range / meridianRadius);
  const double cosLat = std::max(std::cos(degreesToRadians(lat)), 1e-6);
  const double dLon = std::min(180.0, radiansToDegrees(range / (primeRadius * cosLat)));
  spec.southDeg = std::max(-90.0, lat - dLat);
  spec.northDeg = std::min(90.0, lat + dLat);
  spec.westDeg = radar.site.lonDeg - dLon;
  spec.eastDeg = radar.site.lonDeg + dLon;
  const auto count = static_cast<std::size_t>(std::ceil(2.0 * range / horizontalSpacingMeters)) + 1;
  spec.nx = count;
  spec.ny = count;
  // Heights: from the antenna's ground to the top beam edge at the largest range.
  double topHeight = 0.0, ground = 0.0;
  if (!radar.sweeps.empty()) {
    beamHeightAndGroundDistance(range, radar.sweeps.back().elevationDeg + 0.5 * radar.beamWidthDeg,
                                radar.site.antennaHeightEllipsoidMeters, effectiveEarthRadiusMeters(radar.beam, lat),
                                &topHeight, &ground);
  }
  topHeight = std::min(topHeight, radar.site.antennaHeightEllipsoidMeters + 20000.0);
  const double n = (datum == HeightDatum::MeanSeaLevel && geoid)
                       ? geoid->undulationMeters(lat, globe::wrapLongitudeDeg(radar.site.lonDeg))
                       : 0.0;
  fitHeights(std::min(radar.site.antennaHeightEllipsoidMeters, n), topHeight, n, n, datum, levelSpacingMeters, spec);
  return spec;
}

Result<std::vector<float>> resampleRegular(const VolumeSampler& sampler, const RegularGridSpec& spec,
                                           Interpolation interpolation, const GeoidGrid* geoid, unsigned threads,
                                           const std::function<void(std::size_t, std::size_t)>& levelDone) {
  if (auto st = validateRegularGridSpec(spec, std::numeric_limits<std::size_t>::max()); !st) return st.forwardError();
  const bool geographic = spec.kind == RegularGridKind::Geographic;
  if (geographic && spec.datum == HeightDatum::MeanSeaLevel && !geoid)
    return makeError("heights above sea level need the EGM96 geoid grid");
  const std::size_t plane = spec.nx * spec.ny;
  std::vector<float> out(spec.sampleCount(), std::numeric_limits<float>::quiet_NaN());

  // Geographic: the undulation of each column, once.
  std::vector<double> undulation;
  if (geographic && spec.datum == HeightDatum::MeanSeaLevel) {
    undulation.resize(plane);
    const double dLon = axisStep(spec.westDeg, spec.eastDeg, spec.nx);
    const double dLat = axisStep(spec.southDeg, spec.northDeg, spec.ny);
    for (std::size_t j = 0; j < spec.ny; ++j) {
      for (std::size_t i = 0; i < spec.nx; ++i) {
        undulation[j * spec.nx + i] =
            geoid->undulationMeters(spec.southDeg + dLat * static_cast<double>(j),
                                    globe::wrapLongitudeDeg(spec.westDeg + dLon * static_cast<double>(i)));
      }
    }
  }
  const glm::dmat4 enu = globe::enuToEcef({spec.centerLatDeg, spec.centerLonDeg, 0.0});

  auto level = [&](std::size_t k) {
    float* dst = out.data() + k * plane;
    for (std::size_t j = 0; j < spec.ny; ++j) {
      for (std::size_t i = 0; i < spec.nx; ++i) {
        glm::dvec3 ecef;
        if (geographic) {
          const double lat = spec.southDeg + axisStep(spec.southDeg, spec.northDeg, spec.ny) * static_cast<double>(j);
          const double lon = spec.westDeg + axisStep(spec.westDeg, spec.eastDeg, spec.nx) * static_cast<double>(i);
          double h = spec.bottomMeters + axisStep(spec.bottomMeters, spec.topMeters, spec.nz) * static_cast<double>(k);
          if (!undulation.empty()) h += undulation[j * spec.nx + i];
          ecef = globe::geodeticToEcef({lat, globe::wrapLongitudeDeg(lon), h});
        } else {
          const glm::dvec4 local{
              spec.xMinMeters + axisStep(spec.xMinMeters, spec.xMaxMeters, spec.nx) * static_cast<double>(i),
              spec.yMinMeters + axisStep(spec.yMinMeters, spec.yMaxMeters, spec.ny) * static_cast<double>(j),
              spec.zMinMeters + axisStep(spec.zMinMeters, spec.zMaxMeters, spec.nz) * static_cast<double>(k), 1.0};
          ecef = glm::dvec3(enu * local);
        }
        const VolumeSample s = sampler.sample(ecef, interpolation);
        if (s.state == VolumeSample::State::Echo) dst[j * spec.nx + i] = static_cast<float>(s.value);
      }
    }
  };
  std::atomic<std::size_t> levelsDone{0};
  globe::parallelFor(
      spec.nz,
      [&](std::size_t k) {
        level(k);
        const std::size_t done = ++levelsDone;
        if (levelDone) levelDone(done, spec.nz);
      },
      threads);
  return out;
}

std::string nrrdHeader(const RegularGridSpec& spec, const NrrdMetadata& meta, bool gzip) {
  std::ostringstream h;
  h << "NRRD0004\n";
  h << "# Complete NRRD file format specification at:\n";
  h << "# http://teem.sourceforge.net/nrrd/format.html\n";
  h << "# written by atmoglobe convert\n";
  h << "type: float\n";
  h << "dimension: 3\n";
  h << "sizes: " << spec.nx << " " << spec.ny << " " << spec.nz << "\n";
  h << "encoding: " << (gzip ? "gzip" : "raw") << "\n";
  h << "endian: little\n";
  if (!meta.content.empty()) h << "content: " << oneLine(meta.content) << "\n";
  if (spec.kind == RegularGridKind::Geographic) {
    h << "kinds: domain domain domain\n";
    h << "centers: node node node\n";
    h << "labels: \"longitude\" \"latitude\" \"height above " << datumText(spec.datum) << "\"\n";
    h << "units: \"deg\" \"deg\" \"m\"\n";
    h << "axis mins: " << formatNumber(spec.westDeg) << " " << formatNumber(spec.southDeg) << " "
      << formatNumber(spec.bottomMeters) << "\n";
    h << "axis maxs: " << formatNumber(spec.eastDeg) << " " << formatNumber(spec.northDeg) << " "
      << formatNumber(spec.topMeters) << "\n";
    // NRRD: a spacing of NaN means "not known"; a single-sample axis has none.
    auto spacing = [](double first, double last, std::size_t n) {
      return n > 1 ? formatNumber(axisStep(first, last, n)) : std::string("nan");
    };
    h << "spacings: " << spacing(spec.westDeg, spec.eastDeg, spec.nx) << " "
      << spacing(spec.southDeg, spec.northDeg, spec.ny) << " " << spacing(spec.bottomMeters, spec.topMeters, spec.nz)
      << "\n";
  } else {
    // A 3-D space in the local east-north-up frame (metres); the frame's centre is in the
    // key/value pairs, so a user can place it on the Earth.
    h << "space dimension: 3\n";
    h << "space units: \"m\" \"m\" \"m\"\n";
    h << "space origin: (" << formatNumber(spec.xMinMeters) << "," << formatNumber(spec.yMinMeters) << ","
      << formatNumber(spec.zMinMeters) << ")\n";
    const double dx = spec.nx > 1 ? axisStep(spec.xMinMeters, spec.xMaxMeters, spec.nx) : 1.0;
    const double dy = spec.ny > 1 ? axisStep(spec.yMinMeters, spec.yMaxMeters, spec.ny) : 1.0;
    const double dz = spec.nz > 1 ? axisStep(spec.zMinMeters, spec.zMaxMeters, spec.nz) : 1.0;
    h << "space directions: (" << formatNumber(dx) << ",0,0) (0," << formatNumber(dy) << ",0) (0,0," << formatNumber(dz)
      << ")\n";
    h << "kinds: space space space\n";
    h << "centers: node node node\n";
    h << "labels: \"east\" \"north\" \"up\"\n";
  }
  if (!meta.valueUnits.empty()) h << "value_units:=" << oneLine(meta.valueUnits) << "\n";
  h << "missing_values:=NaN (no data and no echo)\n";
  if (spec.kind == RegularGridKind::Geographic) {
    h << "height_datum:=" << datumText(spec.datum) << "\n";
  } else {
    h << "frame:=east-north-up tangent plane of the WGS84 ellipsoid at latitude " << formatNumber(spec.centerLatDeg)
      << " deg, longitude " << formatNumber(spec.centerLonDeg) << " deg, ellipsoid height 0 m\n";
  }
  for (const auto& [key, value] : meta.keyValues) {
    std::string k = oneLine(key);
    std::replace(k.begin(), k.end(), ':', '_');
    h << k << ":=" << oneLine(value) << "\n";
  }
  h << "\n";
  return h.str();
}

namespace {

Result<std::string> gzipBytes(const char* data, std::size_t size) {
  z_stream z{};
  // windowBits 15 + 16: a gzip wrapper, which is what NRRD's "gzip" encoding means.
  if (deflateInit2(&z, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    return makeError("zlib: deflateInit2 failed");
  std::string out;
  out.resize(deflateBound(&z, static_cast<uLong>(std::min<std::size_t>(size, 1u << 30))) + 64);
  std::size_t produced = 0;
  std::size_t consumed = 0;
  int rc = Z_OK;
  while (rc != Z_STREAM_END) {
    // Feed at most 1 GiB at a time (avail_in is 32-bit).
    const std::size_t chunk = std::min<std::size_t>(size - consumed, 1u << 30);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data + consumed));
    z.avail_in = static_cast<uInt>(chunk);
    const int flush = consumed + chunk == size ? Z_FINISH : Z_NO_FLUSH;
    do {
      if (out.size() - produced < 65536) out.resize(out.size() * 2);
      z.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
      z.avail_out = static_cast<uInt>(std::min<std::size_t>(out.size() - produced, 1u << 30));
      const uInt before = z.avail_out;
      rc = deflate(&z, flush);
      produced += before - z.avail_out;
      if (rc == Z_STREAM_ERROR) {
        deflateEnd(&z);
        return makeError("zlib: deflate failed");
      }
    } while (z.avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
    consumed += chunk;
  }
  deflateEnd(&z);
  out.resize(produced);
  return out;
}

}  // namespace

Status writeNrrd(const std::string& path, const RegularGridSpec& spec, const std::vector<float>& values,
                 const NrrdMetadata& meta, bool gzip) {
  if (values.size() != spec.sampleCount())
    return makeError(path + ": " + std::to_string(values.size()) + " values for a grid of " +
                     std::to_string(spec.sampleCount()));
  static_assert(std::numeric_limits<float>::is_iec559, "NRRD float is IEEE 754");
  static_assert(std::endian::native == std::endian::little, "the header says endian: little");
  std::string bytes = nrrdHeader(spec, meta, gzip);
  const std::size_t headerSize = bytes.size();
  const std::size_t dataSize = values.size() * sizeof(float);
  if (gzip) {
    auto packed = gzipBytes(reinterpret_cast<const char*>(values.data()), dataSize);
    if (!packed) return makeError(path + ": " + packed.error());
    bytes += *packed;
  } else {
    bytes.resize(headerSize + dataSize);
    std::memcpy(bytes.data() + headerSize, values.data(), dataSize);
  }
  return writeFileAtomic(path, bytes);
}

namespace {

// The local Cartesian grid that holds a geographic one: centred on the box, x/y the box's
// half-widths along the parallel and the meridian through the centre, z down far enough that the
// box's corners (which the tangent plane leaves below it) are inside.
RegularGridSpec cartesianAround(const RegularGridSpec& geo) {
  RegularGridSpec c;
  c.kind = RegularGridKind::LocalCartesian;
  c.nx = geo.nx;
  c.ny = geo.ny;
  c.nz = geo.nz;
  c.centerLatDeg = 0.5 * (geo.southDeg + geo.northDeg);
  c.centerLonDeg = globe::wrapLongitudeDeg(0.5 * (geo.westDeg + geo.eastDeg));
  const glm::dmat4 toLocal = glm::inverse(globe::enuToEcef({c.centerLatDeg, c.centerLonDeg, 0.0}));
  double xMin = 0, xMax = 0, yMin = 0, yMax = 0, zMin = 0;
  for (double lat : {geo.southDeg, c.centerLatDeg, geo.northDeg}) {
    for (double lon : {geo.westDeg, 0.5 * (geo.westDeg + geo.eastDeg), geo.eastDeg}) {
      const glm::dvec3 p =
          glm::dvec3(toLocal * glm::dvec4(globe::geodeticToEcef({lat, globe::wrapLongitudeDeg(lon), 0.0}), 1.0));
      xMin = std::min(xMin, p.x);
      xMax = std::max(xMax, p.x);
      yMin = std::min(yMin, p.y);
      yMax = std::max(yMax, p.y);
      zMin = std::min(zMin, p.z);
    }
  }
  c.xMinMeters = xMin;
  c.xMaxMeters = xMax;
  c.yMinMeters = yMin;
  c.yMaxMeters = yMax;
  c.zMinMeters = geo.bottomMeters + zMin;
  c.zMaxMeters = geo.topMeters;
  return c;
}

}  // namespace

Result<NrrdExportReport> exportNrrd(const NrrdExportOptions& o) {
  const std::string& in = o.inputPath;
  const GeoidGrid* geoid = nullptr;
  if (o.datum == HeightDatum::MeanSeaLevel && o.kind == RegularGridKind::Geographic) {
    const auto& g = defaultEgm96Grid();
    if (!g) return makeError(g.error() + " (or export heights above the ellipsoid)");
    geoid = &*g;
  }
  NrrdExportReport report;
  NrrdMetadata meta;
  std::optional<GridVolume> grid;
  std::optional<LoadedRadar> radar;
  std::unique_ptr<VolumeSampler> sampler;
  RegularGridSpec spec;
  if (isGridFile(in)) {
    GridReadOptions read;
    read.variable = o.variable;
    read.useGeoid = o.useGeoid;
    read.member = o.member;
    read.ensemble = o.ensemble;
    read.extraIndex = o.gridIndex;
    if (auto st = selectGridTime(o.time, read); !st) return makeError(in + ": " + st.error());
    if (o.cropSouthNorthWestEastDeg) {
      const auto& b = *o.cropSouthNorthWestEastDeg;
      read.crop.southDeg = b[0];
      read.crop.northDeg = b[1];
      read.crop.westDeg = b[2];
      read.crop.eastDeg = b[3];
    }
    auto g = readGridVolume(in, read);
    if (!g) return g.forwardError();
    grid = std::move(*g);
    sampler = std::make_unique<GridSampler>(*grid);
    spec = defaultRegularGrid(*grid, o.datum, geoid);
    report.kindText = "forecast grid";
    report.field = grid->variable;
    report.units = grid->units;
    report.validTime = grid->validTime;
    report.bytesRead = grid->bytesRead;
    report.approximateHeights = grid->approximateHeights;
    report.heightNote = grid->heightNote;
    meta.keyValues.emplace_back("vertical_coordinate", grid->heightNote);
    if (grid->approximateHeights) meta.keyValues.emplace_back("approximate_heights", "yes");
  } else {
    if (!o.time.empty()) return makeError(in + ": --time applies to forecast grids (a radar file is one volume)");
    RadarLoadOptions load;
    load.fieldName = o.variable;
    load.useGeoid = o.useGeoid;
    load.buildRenderLayout = true;
    auto r = loadRadar(in, load);
    if (!r) return r.forwardError();
    radar = std::move(*r);
    sampler = std::make_unique<PolarSampler>(*radar->layout);
    spec = defaultRegularGrid(*radar->layout, o.datum, geoid);
    report.kindText = "radar volume";
    report.field = radar->layout->fieldName;
    report.units = radar->layout->fieldUnits;
    report.validTime = radar->volume.timeIso8601;
    meta.keyValues.emplace_back("site", radar->volume.site.name);
  }
  spec.datum = o.datum;
  if (o.cropSouthNorthWestEastDeg) {
    // The data's own node spacing, kept over the box (a grid read for a box holds the rows and
    // columns just beyond it too, so its node count is not the box's).
    const double dLonDeg = spec.nx > 1 ? (spec.eastDeg - spec.westDeg) / static_cast<double>(spec.nx - 1) : 0.0;
    const double dLatDeg = spec.ny > 1 ? (spec.northDeg - spec.southDeg) / static_cast<double>(spec.ny - 1) : 0.0;
    const auto& b = *o.cropSouthNorthWestEastDeg;
    spec.southDeg = b[0];
    spec.northDeg = b[1];
    spec.westDeg = b[2];
    spec.eastDeg = b[3] < b[2] ? b[3] + 360.0 : b[3];
    if (!o.size) {
      auto count = [](double span, double step) {
        if (!(step > 0.0) || !(span > 0.0)) return std::size_t{2};
        return std::max<std::size_t>(2, static_cast<std::size_t>(std::llround(std::min(span / step, 1e6))) + 1);
      };
      spec.nx = count(spec.eastDeg - spec.westDeg, dLonDeg);
      spec.ny = count(spec.northDeg - spec.southDeg, dLatDeg);
    }
  }
  if (o.heightRangeMeters) {
    spec.bottomMeters = (*o.heightRangeMeters)[0];
    spec.topMeters = (*o.heightRangeMeters)[1];
  }
  if (o.size) {
    spec.nx = (*o.size)[0];
    spec.ny = (*o.size)[1];
    spec.nz = (*o.size)[2];
  }
  if (o.kind == RegularGridKind::LocalCartesian) {
    const bool heightsGiven = o.heightRangeMeters.has_value();
    spec = cartesianAround(spec);
    if (heightsGiven) {
      spec.zMinMeters = (*o.heightRangeMeters)[0];
      spec.zMaxMeters = (*o.heightRangeMeters)[1];
    }
  }
  const std::string where = o.outputPath.empty() ? in : o.outputPath;
  if (auto st = validateRegularGridSpec(spec, o.maxSamples); !st) return makeError(where + ": " + st.error());
  auto values = resampleRegular(*sampler, spec, o.interpolation, geoid, o.threads, o.progress);
  if (!values) return makeError(where + ": " + values.error());
  for (float v : *values) report.finiteValues += std::isfinite(v) ? 1u : 0u;
  meta.content = report.field + (report.units.empty() ? "" : " (" + report.units + ")") + " from " + in;
  meta.valueUnits = report.units;
  meta.keyValues.emplace_back("source", in);
  meta.keyValues.emplace_back("field", report.field);
  if (!report.validTime.empty()) meta.keyValues.emplace_back("valid_time", report.validTime);
  meta.keyValues.emplace_back("interpolation", o.interpolation == Interpolation::Linear ? "linear" : "nearest");
  report.spec = spec;
  if (o.outputPath.empty()) {
    report.values = std::move(*values);
    return report;
  }
  if (auto st = writeNrrd(o.outputPath, spec, *values, meta, o.gzip); !st) return st.forwardError();
  return report;
}

}  // namespace atmoglobe::volume
