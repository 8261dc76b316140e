// A volume loaded for slicing (SliceSource.h).
#include <atmoglobe/volume/SliceSource.h>

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Text.h>
#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/SurfaceField.h>

#include <netcdf.h>

#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <utility>

namespace atmoglobe::volume {

bool fileSaysSynthetic(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  auto file = io::NetcdfFile::open(path);
  if (!file) return false;
  for (const char* name : {"title", "source", "comment"}) {
    if (!file->hasAttribute(file->root(), NC_GLOBAL, name)) continue;
    auto text = file->attributeString(file->root(), NC_GLOBAL, name);
    if (text && text->find("SYNTHETIC") != std::string::npos) return true;
  }
  return false;
}

std::string mosaicOverlapRule(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return {};
  auto file = io::NetcdfFile::open(path);
  if (!file || !file->hasAttribute(file->root(), NC_GLOBAL, "overlap_rule")) return {};
  auto text = file->attributeString(file->root(), NC_GLOBAL, "overlap_rule");
  return text ? *text : std::string();
}

Result<std::unique_ptr<SliceSource>> SliceSource::load(const SliceSourceOptions& o) {
  std::unique_ptr<SliceSource> s(new SliceSource());
  s->path_ = o.path;
  const std::string fileName = std::filesystem::path(o.path).filename().string();
  if (o.kind == SliceSourceOptions::Kind::Radar) {
    RadarLoadOptions load;
    load.fieldName = o.field;
    load.useGeoid = o.useGeoid;
    load.buildRenderLayout = true;
    auto radar = loadRadar(o.path, load);
    if (!radar) return radar.forwardError();
    s->polar_ = std::move(*radar->layout);
    s->sampler_ = std::make_unique<PolarSampler>(*s->polar_);
    s->name_ = radar->volume.site.name.empty() && radar->volume.site.placeName.empty() ? fileName
                                                                                       : siteTitle(radar->volume.site);
    s->field_ = radar->volume.loadedField;
    s->validTime_ = radar->volume.timeIso8601;
    s->nyquist_ = radar->volume.nyquistVelocityMps;
    s->extent_ = polarExtent(*s->polar_);
    const PolarVolume& p = *s->polar_;
    const double re = p.beam.ke * p.beam.earthRadiusMeters.value_or(globe::geocentricRadiusMeters(p.site.latDeg));
    double topHeight = 0.0, ground = 0.0;
    beamHeightAndGroundDistance(p.maxRangeMeters, p.sweeps.back().elevationDeg + 0.5 * p.beamWidthDeg,
                                p.site.antennaHeightEllipsoidMeters, re, &topHeight, &ground);
    double bottomHeight = 0.0;
    beamHeightAndGroundDistance(p.maxRangeMeters, p.sweeps.front().elevationDeg - 0.5 * p.beamWidthDeg,
                                p.site.antennaHeightEllipsoidMeters, re, &bottomHeight, &ground);
    s->minHeight_ = std::min(p.site.antennaHeightEllipsoidMeters, bottomHeight);
    s->maxHeight_ = std::max(p.site.antennaHeightEllipsoidMeters, topHeight);
  } else {
    GridReadOptions read;
    read.variable = o.field;
    read.useGeoid = o.useGeoid;
    read.member = o.member;
    read.ensemble = o.ensemble;
    read.extraIndex = o.gridIndex;
    read.keepPressure = o.keepPressure;
    if (auto st = selectGridTime(o.time, read); !st) return makeError(o.path + ": " + st.error());
    auto grid = readGridVolume(o.path, read);
    if (!grid) return grid.forwardError();
    if (!(grid->valueMin <= grid->valueMax)) {
      return makeError(o.path + ": " + grid->variable + " has no valid value at " +
                       (grid->validTime.empty() ? std::string("the step read") : grid->validTime));
    }
    s->grid_ = std::move(*grid);
    auto sampler = std::make_unique<GridSampler>(*s->grid_);
    s->minHeight_ = sampler->minHeightMeters();
    s->maxHeight_ = sampler->maxHeightMeters();
    s->sampler_ = std::move(sampler);
    s->name_ = fileName;
    std::string variable = s->grid_->variable;
    if (!variable.empty() && variable[0] == '/') variable.erase(0, 1);
    s->field_ = FieldInfo{variable, s->grid_->units, s->grid_->standardName};
    s->validTime_ = s->grid_->validTime;
    s->nyquist_ = std::numeric_limits<double>::quiet_NaN();
    s->extent_ = gridExtent(*s->grid_);
  }
  s->synthetic_ = fileSaysSynthetic(o.path);
  return s;
}

std::string SliceSource::description() const {
  if (polar_) return name_ + " (radar, " + field_.name + ")";
  std::string d =
      name_ + " (grid, " + field_.name + (memberText(*grid_).empty() ? std::string() : ", " + memberText(*grid_)) + ")";
  if (grid_->approximateHeights) d += ", APPROXIMATE heights";
  return d;
}

Result<TransferFunction> SliceSource::transfer(const std::string& colors,
                                               const std::optional<ValueRange>& range) const {
  const bool ranged = range && range->minValue < range->maxValue;
  const ValueRange r = ranged ? *range : valueRange();
  const std::string c = toLowerAscii(colors);
  // A range given for velocity colours is their scale (+- the larger bound).
  const double nyquist = ranged && c == "velocity" ? std::max(std::abs(r.minValue), std::abs(r.maxValue)) : nyquist_;
  auto t = transferForField(colors, field_, nyquist, r);
  if (!t || !ranged) return t;
  // The continuous tables span the range given (transferForField keeps -10..70 for reflectivity).
  using TableMaker = ColorTable (*)(double, double);
  for (auto [name, make] : {std::pair<const char*, TableMaker>{"cividis", &cividisTable},
                            {"viridis", &viridisTable},
                            {"turbo", &turboTable},
                            {"grayscale", &grayscaleTable},
                            {"greens", &greensTable}}) {
    if (c == name || ((c.empty() || c == "auto") && t->colors.name() == name)) t->colors = make(r.minValue, r.maxValue);
  }
  return t;
}

namespace {

std::string metres(double m) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0f m", m);
  return buf;
}

Result<std::vector<double>> parseList(const std::string& text, char separator, const std::string& what) {
  std::vector<double> values;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(separator, start);
    const std::string item(
        trimAscii(std::string_view(text).substr(start, end == std::string::npos ? std::string::npos : end - start)));
    char* stop = nullptr;
    errno = 0;
    const double v = std::strtod(item.c_str(), &stop);
    if (item.empty() || stop != item.c_str() + item.size() || errno != 0 || !std::isfinite(v)) {
      return makeError(what + ": \"" + item + "\" is not a finite number");
    }
    values.push_back(v);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return values;
}

}  // namespace

Result<std::vector<LatLon>> parsePathText(const std::string& text) {
  std::vector<LatLon> points;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(';', start);
    const std::string item = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const std::string what = "path point " + std::to_string(points.size() + 1) + " (\"" + item + "\")";
    auto v = parseList(item, ',', what);
    if (!v) return v.forwardError();
    if (v->size() != 2) return makeError(what + ": expected LAT,LON");
    points.push_back({(*v)[0], (*v)[1]});
    if (end == std::string::npos) break;
    start = end + 1;
  }
  if (points.size() < 2) {
    return makeError("a cross-section path needs at least two points LAT,LON;LAT,LON (got " +
                     std::to_string(points.size()) + ")");
  }
  return points;
}

Result<LatLonBox> parseBoxText(const std::string& text) {
  auto v = parseList(text, ',', "box");
  if (!v) return v.forwardError();
  if (v->size() != 4)
    return makeError("box: expected SOUTH,NORTH,WEST,EAST (4 numbers), got " + std::to_string(v->size()));
  LatLonBox b{(*v)[0], (*v)[1], (*v)[2], (*v)[3]};
  if (b.eastDeg < b.westDeg) b.eastDeg += 360.0;
  if (auto st = validateBox(b, "box"); !st) return st.forwardError();
  return b;
}

Result<SliceGeometry> sliceGeometryFor(const SliceSource& source, const SliceRequest& r) {
  const GeoidGrid* geoid = nullptr;
  if (r.datum == SliceHeightDatum::SeaLevel) {
    const auto& g = defaultEgm96Grid();
    if (!g)
      return makeError("heights above sea level need the EGM96 geoid: " + g.error() +
                       " (or use heights above the ellipsoid)");
    geoid = &*g;
  }
  const LatLonBox extent = source.extent();
  // The volume's heights above the datum (near the middle of its extent: the undulation varies
  // by tens of metres across a radar's range, far less than any slice's height).
  const double n = geoid ? geoid->undulationMeters(0.5 * (extent.southDeg + extent.northDeg),
                                                   0.5 * (extent.westDeg + extent.eastDeg))
                         : 0.0;
  const double lo = source.minHeightMeters() - n, hi = source.maxHeightMeters() - n;
  const std::string datum = toString(r.datum);
  if (r.cappi && r.pressurePa) {
    // An isobaric section: the grid's pressure levels must span the pressure.
    const GridVolume* grid = source.grid();
    if (!grid) return makeError(source.path() + ": an isobaric section (--pressure-hpa) is for grids, not radars");
    // A grid with each value's pressure (terrain-following levels) is checked column by column
    // when sampled (isobaricColumnValues); pressure levels here.
    auto levels = grid->pressurePa.empty()
                      ? pressureLevelsPa(*grid)
                      : Result<std::vector<double>>(std::vector<double>{*r.pressurePa, *r.pressurePa});
    if (!levels) return levels.forwardError();
    const auto [lowest, highest] = std::minmax_element(levels->begin(), levels->end());
    if (!(*r.pressurePa >= *lowest && *r.pressurePa <= *highest))
      return makeError(source.path() + ": " + numberText(*r.pressurePa / 100.0) + " hPa is outside the levels of '" +
                       grid->variable + "', " + numberText(*highest / 100.0) + " to " + numberText(*lowest / 100.0) +
                       " hPa");
    CappiSpec spec;
    spec.pressurePa = r.pressurePa;
    spec.heightMeters = 0.0;
    spec.datum = SliceHeightDatum::Ellipsoid;  // unused: the surface's heights are the grid's
    spec.box = r.box.value_or(extent);
    spec.columns = r.columns;
    spec.rows = r.rows;
    return SliceGeometry::cappi(spec, nullptr);
  }
  if (r.cappi) {
    if (!std::isfinite(r.heightMeters)) return makeError("the CAPPI height must be a finite number");
    if (r.heightMeters < lo || r.heightMeters > hi) {
      return makeError(source.path() + ": a CAPPI at " + metres(r.heightMeters) + " " + datum +
                       " is outside the volume, which has data from " + metres(lo) + " to " + metres(hi) + " " + datum);
    }
    CappiSpec spec;
    spec.heightMeters = r.heightMeters;
    spec.datum = r.datum;
    spec.box = r.box.value_or(extent);
    spec.columns = r.columns;
    spec.rows = r.rows;
    return SliceGeometry::cappi(spec, geoid);
  }
  CrossSectionSpec spec;
  spec.points = r.path;
  spec.datum = r.datum;
  spec.bottomMeters = r.bottomMeters.value_or(std::min(0.0, std::max(lo, -500.0)));
  spec.topMeters = r.topMeters.value_or(std::min(hi, 20000.0));
  spec.columns = r.columns;
  spec.rows = r.rows;
  return SliceGeometry::crossSection(spec, geoid);
}

Result<std::vector<double>> pressureLevelsPa(const GridVolume& grid) {
  if (grid.verticalKind != VerticalKind::Pressure)
    return makeError(grid.path + ": '" + grid.variable + "' is on " + toString(grid.verticalKind) +
                     " levels, not pressure levels: an isobaric section needs a grid on pressure levels or on "
                     "terrain-following pressure levels (hybrid, sigma, WRF eta); height levels carry no pressure");
  const auto toPa = pressureUnitToPascal(grid.levelUnits);
  if (!toPa)
    return makeError(grid.path + ": '" + grid.variable + "': pressure levels in '" + grid.levelUnits +
                     "', not a pressure unit");
  std::vector<double> out;
  for (double v : grid.levelValues) out.push_back(v * *toPa);
  if (out.size() != grid.nz || out.size() < 2)
    return makeError(grid.path + ": '" + grid.variable + "' has " + std::to_string(out.size()) +
                     " pressure levels for " + std::to_string(grid.nz) + " grid levels (two or more needed)");
  return out;
}

Result<std::pair<std::size_t, double>> pressureBracket(const GridVolume& grid, double pressurePa) {
  auto levels = pressureLevelsPa(grid);
  if (!levels) return levels.forwardError();
  const double p = pressurePa;
  // The two levels around p (levels bottom first: pressure falls upwards, or rises in a file
  // stored otherwise) and the weight of the upper one in ln(p).
  for (std::size_t i = 0; i + 1 < levels->size(); ++i) {
    const double a = (*levels)[i], b = (*levels)[i + 1];
    if ((p <= a && p >= b) || (p >= a && p <= b))
      return std::pair{i, a == b ? 0.0 : (std::log(a) - std::log(p)) / (std::log(a) - std::log(b))};
  }
  const auto [lowest, highest] = std::minmax_element(levels->begin(), levels->end());
  return makeError(grid.path + ": " + numberText(p / 100.0) + " hPa is outside the levels of '" + grid.variable +
                   "', " + numberText(*highest / 100.0) + " to " + numberText(*lowest / 100.0) + " hPa");
}

Result<SliceRaster> samplePressureSection(const SliceSource& source, const SliceGeometry& geometry,
                                          Interpolation interpolation, int /*threads*/) {
  const GridVolume* grid = source.grid();
  if (!grid || !dynamic_cast<const GridSampler*>(&source.sampler()))
    return makeError(source.path() + ": an isobaric section is for grids, not radars");
  if (geometry.kind() != SliceGeometry::Kind::Cappi || !geometry.pressurePa())
    return makeError(source.path() + ": not an isobaric section's geometry");
  const double p = *geometry.pressurePa();
  const bool nearest = interpolation == Interpolation::Nearest;
  // Each column's value on the surface (pressure levels or the column's own pressures), then
  // the grid's horizontal interpolation of those values: a one-level grid of the same geometry,
  // so the polar caps and the seam are taken as a sample takes them.
  auto onSurface = isobaricColumnValues(*grid, p, nearest);
  if (!onSurface) return onSurface.forwardError();
  GridVolume surface;
  surface.path = grid->path;
  surface.variable = grid->variable;
  surface.curvilinear = grid->curvilinear;
  surface.nx = grid->nx;
  surface.ny = grid->ny;
  surface.nz = 1;
  surface.lonDeg = grid->lonDeg;
  surface.latDeg = grid->latDeg;
  surface.wrapsLongitude = grid->wrapsLongitude;
  surface.projection = grid->projection;
  surface.rowLengthPoints = grid->rowLengthPoints;
  surface.rowFirstLonDeg = grid->rowFirstLonDeg;
  surface.rowSpacingDeg = grid->rowSpacingDeg;
  surface.values = std::move(*onSurface);
  surface.heightAboveEllipsoidMeters.assign(surface.values.size(), 0.0f);
  setValueRange(surface);
  const GridSampler sampler(surface);
  SliceRaster r;
  r.columns = geometry.columns();
  r.rows = geometry.rows();
  r.values.assign(static_cast<std::size_t>(r.columns) * static_cast<std::size_t>(r.rows),
                  std::numeric_limits<float>::quiet_NaN());
  for (int j = 0; j < r.rows; ++j)
    for (int i = 0; i < r.columns; ++i) {
      const globe::Geodetic g = geometry.geodeticAt(i + 0.5, j + 0.5);
      const auto ij = sampler.horizontalIndex(g.latDeg, g.lonDeg);
      if (!ij) continue;
      GridColumns columns = sampler.columnsAt(*ij);
      if (nearest) columns = heaviestColumn(columns);
      double sum = 0.0;
      bool missing = columns.count == 0;
      for (int c = 0; c < columns.count && !missing; ++c) {
        if (columns.weight[c] == 0.0) continue;
        const double value = sampler.columnValue(columns.column[c], 0);
        if (!std::isfinite(value)) missing = true;
        sum += columns.weight[c] * value;
      }
      if (!missing) r.values[static_cast<std::size_t>(j) * r.columns + i] = static_cast<float>(sum);
    }
  summarizeSliceRaster(r);
  if (r.echoCount == 0)
    return makeError(
        source.path() + ": no data on the " + numberText(p / 100.0) +
        " hPa surface in that box (is the box over the grid?" +
        (grid->pressurePa.empty() ? std::string(")") : std::string(" Is the surface above ground there?)")));
  return r;
}

Result<SliceRaster> sampleSource(const SliceSource& source, const SliceGeometry& geometry, Interpolation interpolation,
                                 int threads) {
  if (geometry.pressurePa()) return samplePressureSection(source, geometry, interpolation, threads);
  SliceRaster raster = sampleSlice({&source.sampler()}, geometry, interpolation, threads);
  if (raster.echoCount + raster.noEchoCount == 0) {
    if (geometry.kind() == SliceGeometry::Kind::Cappi) {
      return makeError(source.path() + ": no data on the CAPPI at " + metres(geometry.cappiHeightMeters()) + " " +
                       toString(geometry.datum()) + " in that box (is the box over the volume?)");
    }
    return makeError(source.path() +
                     ": no data along the cross-section: the path does not cross the volume "
                     "between " +
                     metres(geometry.yBottom()) + " and " + metres(geometry.yTop()) + " " + toString(geometry.datum()));
  }
  return raster;
}

}  // namespace atmoglobe::volume
