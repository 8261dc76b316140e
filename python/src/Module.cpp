// The Python module `atmoglobe` (its compiled part `_atmoglobe`; python/README.md): radar volumes,
// gate positions and grid variables as numpy arrays with their metadata, scenes rendered headless
// to RGBA arrays, PNG files read and written. A thin front end over the libraries, as the CLI is:
// every message is the library's, raised as atmoglobe.Error; the GIL is released while files are
// read and frames drawn.
#include <atmoglobe/engine/AnimationWriter.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/Legend.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/ScenePopulate.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/GateCsv.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/NrrdExport.h>
#include <atmoglobe/volume/RadarLoad.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace py = pybind11;
using namespace atmoglobe;

namespace {

// atmoglobe.Error: a library error, its message as the CLI prints it.
struct ModuleError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <class T>
T check(Result<T> r) {
  if (!r) throw ModuleError(r.error());
  return std::move(*r);
}

// A numpy array owning a copy of `values` in `shape`.
template <class T>
py::array_t<T> array(const std::vector<T>& values, std::vector<py::ssize_t> shape) {
  py::array_t<T> a(shape);
  if (!values.empty()) std::memcpy(a.mutable_data(), values.data(), values.size() * sizeof(T));
  return a;
}

std::string dataDirectory() {
  if (const char* d = std::getenv("ATMOGLOBE_DATA_DIR"); d && *d) return d;
  return ATMOGLOBE_DATA_DIR;
}

py::dict siteDict(const volume::LoadedRadar& r) {
  py::dict site;
  site["name"] = volume::siteTitle(r.volume.site);
  site["lat_deg"] = r.site.site.latDeg;
  site["lon_deg"] = r.site.site.lonDeg;
  site["antenna_height_ellipsoid_m"] = r.site.site.antennaHeightEllipsoidMeters;
  site["datum_note"] = r.site.datumNote;
  return site;
}

py::dict readRadar(const std::string& path, const std::string& field, bool geoid) {
  volume::RadarLoadOptions o;
  o.fieldName = field;
  o.useGeoid = geoid;
  std::optional<Result<volume::LoadedRadar>> loaded;
  {
    py::gil_scoped_release release;
    loaded.emplace(volume::loadRadar(path, o));
  }
  volume::LoadedRadar r = check(std::move(*loaded));
  py::dict out;
  out["path"] = path;
  out["format"] = r.volume.format;
  out["time"] = r.volume.timeIso8601;
  out["field"] = r.volume.loadedField.name;
  out["units"] = r.volume.loadedField.units;
  out["site"] = siteDict(r);
  py::list fields;
  for (const auto& f : r.volume.fields) fields.append(f.name);
  out["fields"] = fields;
  out["warnings"] = r.volume.warnings;
  py::list sweeps;
  for (const volume::Sweep& s : r.volume.sweeps) {
    py::dict d;
    d["fixed_angle_deg"] = s.fixedAngleDeg;
    d["azimuth_deg"] = array(s.azimuthDeg, {static_cast<py::ssize_t>(s.rayCount())});
    d["elevation_deg"] = array(s.elevationDeg, {static_cast<py::ssize_t>(s.rayCount())});
    std::vector<double> range(s.gateCount);
    for (std::uint32_t g = 0; g < s.gateCount; ++g) range[g] = s.gateRangeMeters(g);
    d["range_m"] = array(range, {static_cast<py::ssize_t>(s.gateCount)});
    // No data NaN, no echo -inf (RadarVolume.h's sentinels).
    d["values"] = array(s.values, {static_cast<py::ssize_t>(s.rayCount()), static_cast<py::ssize_t>(s.gateCount)});
    d["start_time"] = s.startTimeIso8601;
    sweeps.append(d);
  }
  out["sweeps"] = sweeps;
  return out;
}

// Every gate's position, as `atmoglobe gates` writes it (exact model, ke 4/3), as columns.
py::dict gates(const std::string& path, const std::string& field, std::optional<int> sweep, bool geoid) {
  volume::RadarLoadOptions o;
  o.fieldName = field;
  o.useGeoid = geoid;
  std::vector<std::int32_t> sweepOf, rayOf, gateOf;
  std::vector<double> azimuth, elevation, range, lat, lon, height, x, y, z;
  std::vector<float> value;
  {
    py::gil_scoped_release release;
    auto loaded = volume::loadRadar(path, o);
    if (!loaded) {
      py::gil_scoped_acquire acquire;
      throw ModuleError(loaded.error());
    }
    const volume::RadarVolume& vol = loaded->volume;
    if (sweep && (*sweep < 0 || static_cast<std::size_t>(*sweep) >= vol.sweeps.size())) {
      py::gil_scoped_acquire acquire;
      throw ModuleError(path + ": sweep " + std::to_string(*sweep) + " out of range (the volume has " +
                        std::to_string(vol.sweeps.size()) + " sweeps)");
    }
    const volume::BeamModel model;
    for (std::size_t k = 0; k < vol.sweeps.size(); ++k) {
      if (sweep && static_cast<std::size_t>(*sweep) != k) continue;
      const volume::Sweep& sw = vol.sweeps[k];
      for (std::size_t i = 0; i < sw.rayCount(); ++i)
        for (std::uint32_t g = 0; g < sw.gateCount; ++g) {
          const double r = sw.gateRangeMeters(g);
          const volume::GatePosition p =
              volume::geolocateGateExact(loaded->site.site, model, sw.azimuthDeg[i], sw.elevationDeg[i], r);
          sweepOf.push_back(static_cast<std::int32_t>(k));
          rayOf.push_back(static_cast<std::int32_t>(i));
          gateOf.push_back(static_cast<std::int32_t>(g));
          azimuth.push_back(sw.azimuthDeg[i]);
          elevation.push_back(sw.elevationDeg[i]);
          range.push_back(r);
          lat.push_back(p.latDeg);
          lon.push_back(p.lonDeg);
          height.push_back(p.heightMeters);
          x.push_back(p.ecef.x);
          y.push_back(p.ecef.y);
          z.push_back(p.ecef.z);
          value.push_back(sw.values.empty() ? std::numeric_limits<float>::quiet_NaN()
                                            : sw.values[i * sw.gateCount + g]);
        }
    }
  }
  const py::ssize_t n = static_cast<py::ssize_t>(lat.size());
  py::dict out;
  out["sweep"] = array(sweepOf, {n});
  out["ray"] = array(rayOf, {n});
  out["gate"] = array(gateOf, {n});
  out["azimuth_deg"] = array(azimuth, {n});
  out["elevation_deg"] = array(elevation, {n});
  out["range_m"] = array(range, {n});
  out["lat_deg"] = array(lat, {n});
  out["lon_deg"] = array(lon, {n});
  out["height_m"] = array(height, {n});
  out["ecef_x"] = array(x, {n});
  out["ecef_y"] = array(y, {n});
  out["ecef_z"] = array(z, {n});
  out["value"] = array(value, {n});
  return out;
}

py::dict readGrid(const std::string& path, const std::string& variable, const std::string& time,
                  std::optional<long> member, const std::string& ensemble, bool geoid) {
  volume::GridReadOptions o;
  o.variable = variable;
  o.useGeoid = geoid;
  if (member) o.member = *member;
  if (auto st = volume::selectGridTime(time, o); !st) throw ModuleError(path + ": " + st.error());
  if (!ensemble.empty()) o.ensemble = check(volume::parseEnsembleStatistic(ensemble));
  std::optional<Result<volume::GridVolume>> read;
  {
    py::gil_scoped_release release;
    read.emplace(volume::readGridVolume(path, o));
  }
  volume::GridVolume g = check(std::move(*read));
  const auto nz = static_cast<py::ssize_t>(g.nz), ny = static_cast<py::ssize_t>(g.ny),
             nx = static_cast<py::ssize_t>(g.nx);
  py::dict out;
  out["path"] = g.path;
  out["format"] = g.format;
  out["variable"] = g.variable;
  out["units"] = g.units;
  out["standard_name"] = g.standardName;
  out["long_name"] = g.longName;
  out["valid_time"] = g.validTime;
  out["times"] = g.times;
  out["member"] = g.member;
  out["ensemble"] = volume::memberText(g);
  out["values"] = array(g.values, {nz, ny, nx});
  out["height_m"] = array(g.heightAboveEllipsoidMeters, {nz, ny, nx});
  out["curvilinear"] = g.curvilinear;
  if (g.curvilinear) {
    out["lat_deg"] = array(g.latDeg, {ny, nx});
    out["lon_deg"] = array(g.lonDeg, {ny, nx});
  } else {
    out["lat_deg"] = array(g.latDeg, {static_cast<py::ssize_t>(g.latDeg.size())});
    out["lon_deg"] = array(g.lonDeg, {static_cast<py::ssize_t>(g.lonDeg.size())});
  }
  out["level_values"] = g.levelValues;
  out["level_units"] = g.levelUnits;
  out["vertical_kind"] = volume::toString(g.verticalKind);
  out["height_note"] = g.heightNote;
  out["approximate_heights"] = g.approximateHeights;
  return out;
}

// A variable or field resampled onto a regular grid, as `atmoglobe convert` writes it (the same
// options; nothing written): values NZ x NY x NX (NaN: no data or no echo) and the grid's axes.
py::dict convert(const std::string& path, const std::string& variable, const std::string& time,
                 std::optional<long> member, const std::string& ensemble, std::optional<std::vector<double>> crop,
                 std::optional<std::vector<double>> heights, std::optional<std::vector<std::size_t>> size,
                 const std::string& grid, const std::string& datum, const std::string& interpolation, bool geoid) {
  volume::NrrdExportOptions o;
  o.inputPath = path;
  o.variable = variable;
  o.time = time;
  if (member) o.member = *member;
  if (!ensemble.empty()) o.ensemble = check(volume::parseEnsembleStatistic(ensemble));
  if (crop) {
    if (crop->size() != 4) throw ModuleError("crop: (south, north, west, east) in degrees");
    o.cropSouthNorthWestEastDeg = std::array<double, 4>{(*crop)[0], (*crop)[1], (*crop)[2], (*crop)[3]};
  }
  if (heights) {
    if (heights->size() != 2) throw ModuleError("heights: (bottom, top) in metres");
    o.heightRangeMeters = std::array<double, 2>{(*heights)[0], (*heights)[1]};
  }
  if (size) {
    if (size->size() != 3) throw ModuleError("size: (nx, ny, nz)");
    o.size = std::array<std::size_t, 3>{(*size)[0], (*size)[1], (*size)[2]};
  }
  if (grid != "geographic" && grid != "cartesian") throw ModuleError("grid: geographic or cartesian, got " + grid);
  if (datum != "msl" && datum != "ellipsoid") throw ModuleError("datum: msl or ellipsoid, got " + datum);
  if (interpolation != "linear" && interpolation != "nearest")
    throw ModuleError("interpolation: linear or nearest, got " + interpolation);
  o.kind = grid == "geographic" ? volume::RegularGridKind::Geographic : volume::RegularGridKind::LocalCartesian;
  o.datum = datum == "msl" ? volume::HeightDatum::MeanSeaLevel : volume::HeightDatum::Ellipsoid;
  o.interpolation = interpolation == "linear" ? volume::Interpolation::Linear : volume::Interpolation::Nearest;
  o.useGeoid = geoid;
  std::optional<Result<volume::NrrdExportReport>> done;
  {
    py::gil_scoped_release release;
    done.emplace(volume::exportNrrd(o));
  }
  volume::NrrdExportReport r = check(std::move(*done));
  const volume::RegularGridSpec& s = r.spec;
  py::dict out;
  out["values"] =
      array(r.values, {static_cast<py::ssize_t>(s.nz), static_cast<py::ssize_t>(s.ny), static_cast<py::ssize_t>(s.nx)});
  out["field"] = r.field;
  out["units"] = r.units;
  out["valid_time"] = r.validTime;
  out["grid"] = grid;
  if (s.kind == volume::RegularGridKind::Geographic) {
    out["west_deg"] = s.westDeg;
    out["east_deg"] = s.eastDeg;
    out["south_deg"] = s.southDeg;
    out["north_deg"] = s.northDeg;
    out["bottom_m"] = s.bottomMeters;
    out["top_m"] = s.topMeters;
  } else {
    out["center_lat_deg"] = s.centerLatDeg;
    out["center_lon_deg"] = s.centerLonDeg;
    out["x_m"] = std::vector<double>{s.xMinMeters, s.xMaxMeters};
    out["y_m"] = std::vector<double>{s.yMinMeters, s.yMaxMeters};
    out["z_m"] = std::vector<double>{s.zMinMeters, s.zMaxMeters};
  }
  out["datum"] = datum;
  return out;
}

py::array_t<std::uint8_t> imageArray(const globe::ImageRGBA8& image) {
  py::array_t<std::uint8_t> a(
      {static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width), static_cast<py::ssize_t>(4)});
  std::memcpy(a.mutable_data(), image.pixels.data(), image.pixels.size());
  return a;
}

// Renders a scene (JSON text or a file) headless: an H x W x 4 array, the legend drawn unless
// `legend` is false, and where the time went (ms): the GL context, loading the scene (reading,
// placing and uploading its files), drawing the frame (to the pixels read back), the legend.
py::tuple renderScene(const std::string& jsonText, const std::string& file, bool legend, bool strict) {
  globe::ImageRGBA8 image;
  std::string error;
  double contextMs = 0.0, loadMs = 0.0, drawMs = 0.0, legendMs = 0.0;
  {
    py::gil_scoped_release release;
    using Clock = std::chrono::steady_clock;
    auto since = [](Clock::time_point t0) {
      return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    };
    [&] {
      auto scene = file.empty() ? engine::parseSceneJson(jsonText, "scene", std::filesystem::current_path().string(),
                                                         dataDirectory())
                                : engine::loadSceneFile(file, dataDirectory());
      if (!scene) return void(error = scene.error());
      // A context for this call, current on this thread (the caller's thread may change between
      // calls: a Dask worker's).
      auto t0 = Clock::now();
      auto context = engine::HeadlessContextGL::create();
      if (!context) return void(error = context.error());
      contextMs = since(t0);
      t0 = Clock::now();
      auto loader = engine::openImagery(scene->imagery, {});
      if (!loader) return void(error = loader.error());
      auto renderer = engine::SceneRendererGL::create(*loader);
      if (!renderer) return void(error = renderer.error());
      std::vector<engine::Marker> markers = scene->markers;
      std::vector<std::string> inputErrors;
      if (auto st = engine::populateScene(**renderer, *scene, &markers, strict ? nullptr : &inputErrors); !st)
        return void(error = st.error());
      if (!inputErrors.empty()) return void(error = inputErrors.front());
      loadMs = since(t0);
      t0 = Clock::now();
      auto target = engine::FramebufferGL::create(scene->widthPx, scene->heightPx);
      if (!target) return void(error = target.error());
      const engine::Camera camera(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
      auto drawn = (*renderer)->renderToImage(camera, markers, **target);
      if (!drawn) return void(error = drawn.error());
      drawMs = since(t0);
      t0 = Clock::now();
      if (legend)
        if (auto st = engine::drawFrameLegend(*drawn, (*renderer)->legendFor(camera)); !st)
          return void(error = st.error());
      legendMs = since(t0);
      image = std::move(*drawn);
    }();
  }
  if (!error.empty()) throw ModuleError(error);
  py::dict timings;
  timings["context_ms"] = contextMs;
  timings["load_ms"] = loadMs;
  timings["draw_ms"] = drawMs;
  timings["legend_ms"] = legendMs;
  return py::make_tuple(imageArray(image), timings);
}

py::array_t<std::uint8_t> readPng(const std::string& path) { return imageArray(check(globe::decodeImageFile(path))); }

void writePng(const std::string& path, py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast> rgba) {
  if (rgba.ndim() != 3 || rgba.shape(2) != 4)
    throw ModuleError(path + ": an image is an H x W x 4 array of uint8 (RGBA)");
  globe::ImageRGBA8 image =
      globe::ImageRGBA8::filled(static_cast<int>(rgba.shape(1)), static_cast<int>(rgba.shape(0)), glm::u8vec4(0));
  std::memcpy(image.pixels.data(), rgba.data(), image.pixels.size());
  if (auto st = globe::writePng(path, image); !st) throw ModuleError(st.error());
}

// Frames (PNG paths, in order) into an animated GIF or an MP4, as `render --animation` does.
void writeAnimation(const std::vector<std::string>& frames, const std::string& path, double fps) {
  if (!(fps > 0.0 && fps <= 60.0)) throw ModuleError(path + ": frames per second must be in (0, 60]");
  const std::string ext = std::filesystem::path(path).extension().string();
  std::string error;
  {
    py::gil_scoped_release release;
    [&] {
      if (ext == ".gif" || ext == ".GIF") {
        std::unique_ptr<engine::GifAnimationWriter> gif;
        for (const std::string& f : frames) {
          auto image = globe::decodeImageFile(f);
          if (!image) return void(error = image.error());
          if (!gif) {
            auto created = engine::GifAnimationWriter::create(path, image->width, image->height,
                                                              static_cast<int>(std::lround(1000.0 / fps)));
            if (!created) return void(error = created.error());
            gif = std::move(*created);
          }
          if (auto st = gif->addFrame(*image); !st) return void(error = st.error());
        }
        if (gif)
          if (auto st = gif->finish(); !st) error = st.error();
        return;
      }
      if (ext != ".mp4" && ext != ".MP4") return void(error = path + ": the name must end in .gif or .mp4");
      // ffmpeg takes a numbered pattern: the frames linked as 00000.png ... in a directory of ours.
      std::error_code ec;
      std::string pattern = (std::filesystem::temp_directory_path(ec) / "atmoglobe-mp4-XXXXXX").string();
      if (!::mkdtemp(pattern.data())) return void(error = path + ": cannot make a directory for the frames");
      const std::filesystem::path dir = pattern;
      for (std::size_t i = 0; i < frames.size() && error.empty(); ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "%05zu.png", i);
        std::filesystem::create_symlink(std::filesystem::absolute(frames[i]), dir / name, ec);
        if (ec) error = frames[i] + ": " + ec.message();
      }
      if (error.empty())
        if (auto st = engine::encodeMp4((dir / "%05d.png").string(), fps, path); !st) error = st.error();
      std::filesystem::remove_all(dir, ec);
    }();
  }
  if (!error.empty()) throw ModuleError(error);
}

}  // namespace

PYBIND11_MODULE(_atmoglobe, m) {
  m.doc() = "atmoglobe: radar volumes and forecast grids on an ellipsoidal globe (compiled part)";
  static py::exception<ModuleError> error(m, "Error", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ModuleError& e) {
      error(e.what());
    }
  });
  m.def("read_radar", &readRadar, py::arg("path"), py::arg("field") = "", py::arg("geoid") = true,
        "A radar volume (one file or a set of files of one volume): metadata and, per sweep, ray angles, gate "
        "ranges and the field's values (rays x gates; NaN no data, -inf no echo).");
  m.def("gates", &gates, py::arg("path"), py::arg("field") = "", py::arg("sweep") = py::none(), py::arg("geoid") = true,
        "Every gate's position (exact WGS84 model, ke 4/3) and value as columns, as `atmoglobe gates` writes them.");
  m.def("read_grid", &readGrid, py::arg("path"), py::arg("variable") = "", py::arg("time") = "",
        py::arg("member") = py::none(), py::arg("ensemble") = "", py::arg("geoid") = true,
        "A forecast-grid variable at one time: values (levels bottom first x rows south to north x columns west to "
        "east), heights above the WGS84 ellipsoid, coordinates and metadata.");
  m.def("convert", &convert, py::arg("path"), py::arg("variable") = "", py::arg("time") = "",
        py::arg("member") = py::none(), py::arg("ensemble") = "", py::arg("crop") = py::none(),
        py::arg("heights") = py::none(), py::arg("size") = py::none(), py::arg("grid") = "geographic",
        py::arg("datum") = "msl", py::arg("interpolation") = "linear", py::arg("geoid") = true,
        "A grid variable or radar field resampled onto a regular grid as `atmoglobe convert` writes it (values "
        "NZ x NY x NX, NaN for no data or no echo, and the grid's extent); nothing is written.");
  m.def("_render", &renderScene, py::arg("json"), py::arg("file"), py::arg("legend") = true, py::arg("strict") = true);
  m.def("read_png", &readPng, py::arg("path"), "A PNG (or JPEG) file as an H x W x 4 uint8 array.");
  m.def("write_png", &writePng, py::arg("path"), py::arg("rgba"), "Writes an H x W x 4 uint8 array as a PNG.");
  m.def("_write_animation", &writeAnimation, py::arg("frames"), py::arg("path"), py::arg("fps"));
  m.attr("data_directory") = dataDirectory();
}
