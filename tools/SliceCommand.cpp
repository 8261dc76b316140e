// `atmoglobe slice (--radar FILE [--field F] | --grid FILE [--var V] [--time T])
//  (--height-m H [--box S,N,W,E] | --path "LAT,LON;LAT,LON[;...]" [--heights-m BOTTOM,TOP])
//  [--datum msl|ellipsoid] [--colors NAME] [--range MIN,MAX] [--interpolation linear|nearest]
//  [--size WxH] -o OUT.png`: a CAPPI or a vertical cross-section as a PNG with axes, a colour key,
// title and time. The logic lives in volume/Slice.h, volume/SliceSource.h and engine/SlicePlot.h.
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/map/Contours.h>
#include <atmoglobe/map/Gshhg.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/SliceSource.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace atmoglobe::tools {
namespace {

struct SliceOptions {
  std::string radar, grid, field, time;
  std::optional<double> heightMeters;
  std::optional<double> pressureHpa;  ///< --pressure-hpa: an isobaric section of a pressure-level grid
  std::string path, box, heights, datum = "msl", colors = "auto", range, interpolation = "linear", size, output;
  bool noGeoid = false;
  bool noMap = false;                 ///< --no-map: no coastlines or borders on a CAPPI
  std::vector<std::string> overlays;  ///< --overlay FILE: vector files drawn on a CAPPI
  int threads = 0;
  long member = -1;
  std::string ensemble;
  std::map<std::string, std::size_t> gridIndex;
  std::string contourVar, contourInterval, contourValues;  ///< --contour-*: lines over a horizontal section
  bool spaghetti = false;                                  ///< --spaghetti: the contours of every ensemble member
};

Result<std::pair<double, double>> parsePair(const std::string& text, const std::string& what) {
  const auto comma = text.find(',');
  char* e1 = nullptr;
  char* e2 = nullptr;
  if (comma == std::string::npos) return makeError(what + ": expected two numbers A,B, got \"" + text + "\"");
  const std::string a = text.substr(0, comma), b = text.substr(comma + 1);
  const double x = std::strtod(a.c_str(), &e1), y = std::strtod(b.c_str(), &e2);
  if (a.empty() || b.empty() || *e1 || *e2 || !std::isfinite(x) || !std::isfinite(y) || !(x < y)) {
    return makeError(what + ": expected two finite numbers A,B with A < B, got \"" + text + "\"");
  }
  return std::pair{x, y};
}

int usage(const std::string& message) {
  std::cerr << "atmoglobe slice: " << message << "\n";
  return 2;
}

int runSlice(const SliceOptions& o) {
  const char* cmd = "slice";
  const auto start = std::chrono::steady_clock::now();
  if (o.radar.empty() == o.grid.empty()) return usage("give exactly one of --radar FILE or --grid FILE");
  if (int(o.heightMeters.has_value()) + int(o.pressureHpa.has_value()) + int(!o.path.empty()) != 1)
    return usage("give exactly one of --height-m H, --pressure-hpa P or --path POINTS");
  if (o.pressureHpa && o.grid.empty())
    return usage("--pressure-hpa is for --grid (a grid on pressure, hybrid, sigma or WRF eta levels)");
  if (!o.time.empty() && o.grid.empty()) return usage("--time is for --grid");
  if (o.member >= 0 && o.grid.empty()) return usage("--member is for --grid");
  if (!o.ensemble.empty() && o.grid.empty()) return usage("--ensemble is for --grid");
  if (!o.gridIndex.empty() && o.grid.empty()) return usage("--grid-index is for --grid");
  if (!o.box.empty() && !o.heightMeters && !o.pressureHpa)
    return usage("--box is for a horizontal section (--height-m or --pressure-hpa)");
  if (!o.heights.empty() && o.path.empty()) return usage("--heights-m is for a cross-section (--path)");
  const bool contours = !o.contourVar.empty() || !o.contourInterval.empty() || !o.contourValues.empty();
  if (o.spaghetti && o.contourValues.empty()) return usage("--spaghetti needs --contour-values (e.g. 552)");
  if (o.spaghetti && o.grid.empty()) return usage("--spaghetti is for --grid (an ensemble)");
  if (contours && o.path.size())
    return usage("contours are drawn on a horizontal section (--height-m, --pressure-hpa)");
  if (!o.contourVar.empty() && o.grid.empty()) return usage("--contour-var is for --grid");
  if (contours && o.contourInterval.empty() && o.contourValues.empty())
    return usage("--contour-var needs --contour-interval X or --contour-values A,B,...");
  std::optional<map::ContourLevels> contourLevels;
  if (contours) {
    auto levels = map::parseContourLevels(o.contourInterval, o.contourValues);
    if (!levels) return usage(levels.error());
    contourLevels = *levels;
  }
  if (o.datum != "msl" && o.datum != "ellipsoid") return usage("--datum: msl or ellipsoid, got \"" + o.datum + "\"");
  if (o.interpolation != "linear" && o.interpolation != "nearest") {
    return usage("--interpolation: linear or nearest, got \"" + o.interpolation + "\"");
  }
  volume::SliceRequest request;
  request.cappi = o.heightMeters.has_value() || o.pressureHpa.has_value();
  request.datum = o.datum == "msl" ? volume::SliceHeightDatum::SeaLevel : volume::SliceHeightDatum::Ellipsoid;
  if (request.cappi) {
    if (o.heightMeters) request.heightMeters = *o.heightMeters;
    if (o.pressureHpa) {
      if (!(*o.pressureHpa > 0.0 && *o.pressureHpa < 2000.0))
        return usage("--pressure-hpa: a pressure in (0, 2000) hPa, got " + std::to_string(*o.pressureHpa));
      request.pressurePa = *o.pressureHpa * 100.0;
    }
    if (!o.box.empty()) {
      auto box = volume::parseBoxText(o.box);
      if (!box) return usage("--" + box.error());
      request.box = *box;
    }
  } else {
    auto path = volume::parsePathText(o.path);
    if (!path) return usage("--path: " + path.error());
    request.path = *path;
    if (!o.heights.empty()) {
      auto h = parsePair(o.heights, "--heights-m");
      if (!h) return usage(h.error());
      request.bottomMeters = h->first;
      request.topMeters = h->second;
    }
  }
  std::optional<volume::ValueRange> range;
  if (!o.range.empty()) {
    auto r = parsePair(o.range, "--range");
    if (!r) return usage(r.error());
    range = volume::ValueRange{r->first, r->second};
  }
  int width = 0, height = 0;
  if (!o.size.empty()) {
    if (auto st = parseSize(o.size, &width, &height); !st) return usage(st.error());
  }

  volume::SliceSourceOptions load;
  load.kind = o.radar.empty() ? volume::SliceSourceOptions::Kind::Grid : volume::SliceSourceOptions::Kind::Radar;
  load.path = o.radar.empty() ? o.grid : o.radar;
  load.field = o.field;
  load.time = o.time;
  load.member = o.member;
  load.gridIndex = o.gridIndex;
  if (!o.ensemble.empty()) {
    auto stat = volume::parseEnsembleStatistic(o.ensemble);
    if (!stat) return usage("--ensemble: " + stat.error());
    load.ensemble = *stat;
  }
  load.useGeoid = !o.noGeoid;
  load.keepPressure = o.pressureHpa.has_value();
  auto source = volume::SliceSource::load(load);
  if (!source) return fail(cmd, source.error());
  auto transfer = (*source)->transfer(o.colors, range);
  if (!transfer) return fail(cmd, transfer.error());

  // The image size (CAPPI: the box's shape by default), then the plot area, sampled one raster
  // pixel per image pixel.
  if (width == 0) {
    width = request.cappi ? 900 : 1100;
    if (request.cappi) {
      auto probe = volume::sliceGeometryFor(**source, request);
      if (!probe) return fail(cmd, probe.error());
      const volume::LatLonBox box{probe->yBottom(), probe->yTop(), probe->xFirst(), probe->xLast()};
      height = engine::cappiImageHeightFor(box, width);
    } else {
      height = 560;
    }
  }
  request.columns = request.rows = 16;
  auto probe = volume::sliceGeometryFor(**source, request);
  if (!probe) return fail(cmd, probe.error());
  auto layout = engine::layoutSlicePlot(*probe, width, height);
  if (!layout) return usage("--size: " + layout.error());
  request.columns = layout->width();
  request.rows = layout->height();
  auto geometry = volume::sliceGeometryFor(**source, request);
  if (!geometry) return fail(cmd, geometry.error());
  auto raster = volume::sampleSource(
      **source, *geometry,
      o.interpolation == "nearest" ? volume::Interpolation::Nearest : volume::Interpolation::Linear, o.threads);
  if (!raster) return fail(cmd, raster.error());
  engine::SlicePlotOptions plot = engine::slicePlotOptionsFor(**source, *geometry, *transfer, width, height);
  if (request.cappi && !o.noMap) {
    // Coastlines and borders as on the globe; a missing GSHHG install is said and left out.
    char resolution = '?';
    if (auto st = engine::addSliceCoastlines(plot, *geometry, *layout, map::defaultGshhgDirectory(), &resolution); !st)
      std::cerr << "atmoglobe slice: warning: no coastlines or borders on the picture: " << st.error()
                << " (Debian package gmt-gshhg; --no-map leaves them out)\n";
    else std::cerr << "atmoglobe slice: map lines: GSHHG resolution " << resolution << "\n";
  }
  if (request.cappi)  // the user's own overlays: one that cannot be read is an error
    if (auto st = engine::addSliceOverlays(plot, o.overlays); !st) return fail(cmd, st.error());
  std::size_t contourCount = 0;
  if (contourLevels) {
    // Contours of the field shown, or of another variable of the same grid on the same section
    // (same time, member or statistic, indices); with --spaghetti, of every ensemble member.
    const auto interpolation = o.interpolation == "nearest" ? volume::Interpolation::Nearest
                                                            : volume::Interpolation::Linear;
    std::string what;
    // The contour lines of `options`' variable on the section (the raster shown when it is that).
    auto linesOf = [&](const volume::SliceSourceOptions& options, bool shown) -> Result<std::vector<map::ContourLine>> {
      std::unique_ptr<volume::SliceSource> loaded;
      const volume::SliceSource* contoured = source->get();
      if (!shown) {
        auto l = volume::SliceSource::load(options);
        if (!l) return l.forwardError();
        loaded = std::move(*l);
        contoured = loaded.get();
      }
      auto values = shown ? Result<volume::SliceRaster>(*raster)
                          : volume::sampleSource(*contoured, *geometry, interpolation, o.threads);
      if (!values) return values.forwardError();
      // Geopotential is drawn as forecasters read it: geopotential height in decametres (the
      // interval and values are then in dam: 500 hPa every 6 dam).
      what = contoured->field().name;
      if (const auto toSi = volume::geopotentialUnitToSi(contoured->field().units)) {
        for (float& v : values->values) v = static_cast<float>(v * *toSi / volume::kStandardGravity / 10.0);
        what += " as geopotential height (dam)";
      } else if (!contoured->field().units.empty()) {
        what += " (" + contoured->field().units + ")";
      }
      map::ContourRaster cr;
      cr.values = values->values.data();
      cr.columns = values->columns;
      cr.rows = values->rows;
      cr.westDeg = geometry->xFirst();
      cr.northDeg = geometry->yTop();
      cr.dxDeg = (geometry->xLast() - geometry->xFirst()) / values->columns;
      cr.dyDeg = (geometry->yTop() - geometry->yBottom()) / values->rows;
      return map::contourLines(cr, *contourLevels);
    };
    volume::SliceSourceOptions contourOptions = load;
    if (!o.contourVar.empty()) contourOptions.field = o.contourVar;
    std::string at;
    if (contourLevels->interval) {
      at = "every " + map::contourLabel(*contourLevels->interval);
    } else {
      for (std::size_t i = 0; i < contourLevels->values.size(); ++i)
        at += (i ? ", " : "at ") + map::contourLabel(contourLevels->values[i]);
    }
    if (!o.spaghetti) {
      auto lines = linesOf(contourOptions, o.contourVar.empty());
      if (!lines) return fail(cmd, (o.contourVar.empty() ? "" : "--contour-var: ") + lines.error());
      contourCount = lines->size();
      plot.contours.push_back({std::move(*lines), {0, 0, 0, 255}, 1.4, true});
      plot.subtitle += "; contours: " + what + " " + at;
    } else {
      // One set of lines per member, in colours of their own (member k: a hue k/N of the wheel).
      volume::GridReadOptions which;
      which.variable = contourOptions.field;
      which.useGeoid = load.useGeoid;
      which.extraIndex = load.gridIndex;
      if (auto st = volume::selectGridTime(load.time, which); !st) return fail(cmd, st.error());
      auto members = volume::ensembleMemberSelections(load.path, which);
      if (!members) return fail(cmd, "--spaghetti: " + members.error());
      const std::size_t n = members->size();
      for (std::size_t k = 0; k < n; ++k) {
        volume::SliceSourceOptions m = contourOptions;
        m.member = (*members)[k].member;
        for (const auto& [dimension, index] : (*members)[k].extraIndex) m.gridIndex[dimension] = index;
        m.ensemble.reset();
        auto lines = linesOf(m, false);
        if (!lines) return fail(cmd, "--spaghetti: member " + std::to_string(k) + ": " + lines.error());
        contourCount += lines->size();
        const double hue = 6.0 * static_cast<double>(k) / static_cast<double>(n);
        auto channel = [&](double offset) {
          const double x = std::fmod(hue + offset, 6.0);
          const double v = x < 1.0 ? x : x < 3.0 ? 1.0 : x < 4.0 ? 4.0 - x : 0.0;
          return static_cast<std::uint8_t>(std::lround(30.0 + 190.0 * v));
        };
        plot.contours.push_back({std::move(*lines), {channel(2.0), channel(0.0), channel(4.0), 255}, 1.3, false});
      }
      plot.subtitle += "; spaghetti: " + what + " " + at + ", " + std::to_string(n) + " members";
    }
  }
  auto image = engine::drawSlicePlot(*raster, *geometry, plot);
  if (!image) return fail(cmd, image.error());
  if (auto st = globe::writePng(o.output, *image); !st) return fail(cmd, st.error());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  char figures[256];
  std::snprintf(figures, sizeof figures, "%d x %d px; %zu echo, %zu no-echo, %zu no-data pixels", image->width,
                image->height, raster->echoCount, raster->noEchoCount, raster->noDataCount);
  if (contourLevels)
    std::snprintf(figures + std::strlen(figures), sizeof figures - std::strlen(figures), "; %zu contour lines",
                  contourCount);
  std::cout << "wrote " << o.output << ": " << plot.title << "; " << plot.subtitle << "; " << figures;
  if (raster->echoCount) {
    char values[128];
    std::snprintf(values, sizeof values, "; echo %.1f .. %.1f %s", raster->minEcho, raster->maxEcho,
                  (*source)->field().units.c_str());
    std::cout << values;
  }
  char time[64];
  std::snprintf(time, sizeof time, "; %.2f s\n", seconds);
  std::cout << time;
  return 0;
}

}  // namespace

Command addSliceCommand(CLI::App& root) {
  auto opts = std::make_shared<SliceOptions>();
  CLI::App* c = root.add_subcommand(
      "slice",
      "A CAPPI (horizontal slice at a height) or a vertical cross-section along a geodesic path through a radar "
      "volume or a forecast grid, as a PNG with axes, colour key, title and valid time");
  c->add_option("--radar", opts->radar, "Radar file (CfRadial, ODIM_H5, NEXRAD Level II)");
  c->add_option("--grid", opts->grid, "Forecast grid (CF or WRF netCDF, GRIB 1 or 2)");
  c->add_option("--field,--var", opts->field, "Radar field or grid variable (default: the file's default)");
  c->add_option("--time", opts->time, "Grid time step: an index (0 = first) or an ISO 8601 UTC time");
  c->add_option("--member", opts->member,
                "Grid ensemble member (GRIB `number`, listed by `atmoglobe info`; default: the first)")
      ->check(CLI::NonNegativeNumber);
  c->add_option("--ensemble", opts->ensemble,
                "Grid: a statistic over every ensemble member instead of one: mean, spread (standard deviation), min, "
                "max, or prob:>=VALUE (also >, <=, <; the percentage of members passing)");
  addGridIndexOption(c, opts->gridIndex);
  c->add_option("--height-m", opts->heightMeters, "CAPPI height (m above the datum)");
  c->add_option(
      "--pressure-hpa", opts->pressureHpa,
      "Grids on pressure, hybrid, sigma or WRF eta levels: a horizontal section on this isobaric surface (hPa; between levels "
      "interpolated linearly in ln p), e.g. 500");
  c->add_option("--box", opts->box,
                "CAPPI box SOUTH,NORTH,WEST,EAST (deg; west > east crosses the antimeridian); default: the volume's "
                "extent");
  c->add_option("--path", opts->path,
                "Cross-section points \"LAT,LON;LAT,LON[;...]\" (deg), joined by WGS84 geodesics");
  c->add_option("--heights-m", opts->heights,
                "Cross-section heights BOTTOM,TOP (m above the datum); default 0 .. the volume's top, at most 20 km");
  c->add_option("--datum", opts->datum,
                "Heights above msl (mean sea level, EGM96 geoid; default) or ellipsoid (WGS84)");
  c->add_option("--colors", opts->colors,
                "Colour table as in render: auto (by the field), NWS, velocity, viridis, turbo, grayscale, greens, "
                "cividis or a .pal file");
  c->add_option("--range", opts->range, "Value range MIN,MAX of a continuous colour table (field units)");
  c->add_option("--interpolation", opts->interpolation, "linear (default) or nearest, as the samplers define them");
  c->add_option("--size", opts->size, "Image size WxH (default: 900 wide for a CAPPI, 1100x560 for a cross-section)");
  c->add_flag("--no-geoid", opts->noGeoid, "Take heights above sea level in the file as ellipsoidal");
  c->add_flag("--no-map", opts->noMap, "No GSHHG coastlines or borders on a CAPPI (drawn by default, as on the globe)");
  c->add_option("--overlay", opts->overlays,
                "A vector file (GeoJSON, shapefile, KML, GeoPackage ... through GDAL) drawn on a CAPPI; repeatable");
  c->add_option("--contour-var", opts->contourVar,
                "Grids: contour lines of this variable of the same file over the section (default: the field shown), "
                "e.g. z over t at 500 hPa");
  c->add_option("--contour-interval", opts->contourInterval,
                "Contour lines at every multiple of this value (the contoured variable's units), labelled");
  c->add_option("--contour-values", opts->contourValues, "Contour lines at these values A,B,... instead, labelled");
  c->add_flag("--spaghetti", opts->spaghetti,
              "With --contour-values: those contours of every ensemble member in one picture, a colour per member");
  c->add_option("--threads", opts->threads, "Sampling threads (default: all cores)")->check(CLI::Range(0, 256));
  c->add_option("-o,--output", opts->output, "Output PNG (written atomically)")->required();
  return Command{c, [opts] { return runSlice(*opts); }};
}

}  // namespace atmoglobe::tools
