#include <atmoglobe/bench/GridViews.h>

#include <atmoglobe/engine/GridVolumeGL.h>
#include <atmoglobe/engine/ViewCulling.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/RenderCamera.h>
#include <atmoglobe/volume/SyntheticGrid.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <ostream>

namespace atmoglobe::bench {

namespace fs = std::filesystem;

namespace {

// Bump when a built-in grid's content changes: the file name and the reference keys hold it.
constexpr const char* kRegionalName = "synthetic_regional_v1.nc";
constexpr const char* kGlobalName = "synthetic_global_v1.nc";

struct ViewSpec {
  std::string suffix;
  double targetLatDeg, targetLonDeg, bearingDeg, distanceMeters, heightMeters, fovYDeg;
  bool down;
};

/// The views of a grid: built-ins by their keys, a file by its extent.
std::vector<ViewSpec> viewSpecs(const BenchVolume& v) {
  const volume::GridVolume& g = *v.grid;
  if (v.key == "regional") {
    const double lat = 0.5 * (g.latDeg.front() + g.latDeg.back()), lon = 0.5 * (g.lonDeg.front() + g.lonDeg.back());
    return {{"oblique", lat, lon, 200.0, 250e3, 100e3, 50.0, false}, {"down", lat, lon, 0.0, 0.0, 2500e3, 50.0, true}};
  }
  if (v.key == "global") {
    // The north Atlantic cyclone of volume::writeSyntheticGlobalGrid at its first step.
    // "far": the whole disc small in the picture, where a pixel spans several columns (the level
    // of detail's case).
    return {{"space", 15.0, -40.0, 0.0, 0.0, 12000e3, 45.0, true},
            {"cyclone", 19.0, -62.0, 200.0, 900e3, 450e3, 50.0, false},
            {"far", 15.0, -40.0, 0.0, 0.0, 35000e3, 45.0, true}};
  }
  // A file: around its centre, distances from its size.
  double latMin = 90, latMax = -90, lonMin = 1e9, lonMax = -1e9;
  for (std::size_t j = 0; j < g.ny; ++j)
    for (std::size_t i = 0; i < g.rowLength(j); ++i) {  // a reduced grid: its row's points
      latMin = std::min(latMin, g.latDegAt(j, i)), latMax = std::max(latMax, g.latDegAt(j, i));
      lonMin = std::min(lonMin, g.lonDegAt(j, i)), lonMax = std::max(lonMax, g.lonDegAt(j, i));
    }
  const double lat = 0.5 * (latMin + latMax), lon = g.wrapsLongitude ? 0.0 : 0.5 * (lonMin + lonMax);
  const double sizeMeters = std::max(latMax - latMin, (lonMax - lonMin) * std::cos(degreesToRadians(lat))) * 111e3;
  const double down = std::min(1.2e7, std::max(2e4, 1.2 * sizeMeters));
  return {{"oblique", lat, lon, 200.0, std::min(2e6, 0.3 * sizeMeters), std::min(1e6, 0.12 * sizeMeters), 50.0, false},
          {"down", lat, lon, 0.0, 0.0, down, 50.0, true}};
}

}  // namespace

std::vector<GridBenchFile> builtinGridFiles(const fs::path& dir) {
  GridBenchFile regional{"regional", (dir / kRegionalName).string(), "dbz", 3, -1, true};
  GridBenchFile global{"global", (dir / kGlobalName).string(), "dbz", 0, -1, true};
  return {regional, global};
}

Status ensureGridFile(const GridBenchFile& file, std::ostream& log) {
  std::error_code ec;
  if (!file.synthetic || fs::exists(file.path, ec)) return Ok{};
  fs::create_directories(fs::path(file.path).parent_path(), ec);
  log << "writing the SYNTHETIC " << file.key << " grid to " << file.path << " ..." << std::flush;
  const auto t0 = std::chrono::steady_clock::now();
  volume::SyntheticGridSummary sum;
  Status st = file.key == "global" ? volume::writeSyntheticGlobalGrid(file.path, {}, &sum)
                                   : volume::writeSyntheticGrid(file.path, {}, &sum);
  if (!st) return st;
  log << " " << sum.nx << " x " << sum.ny << " x " << sum.levels << " x " << sum.times << ", "
      << static_cast<double>(sum.fileBytes) / 1e6 << " MB, "
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s\n";
  return Ok{};
}

Result<BenchVolume> loadGridBenchVolume(const GridBenchFile& file) {
  BenchVolume v;
  v.key = file.key;
  v.path = file.path;
  v.kind = VolumeKind::Grid;
  if (file.synthetic) v.identity = "builtin:" + fs::path(file.path).filename().string();
  v.gridRead.variable = file.variable;
  v.gridRead.timeIndex = file.timeIndex;
  v.gridRead.member = file.member;
  auto g = volume::readGridVolume(file.path, v.gridRead);
  if (!g) return g.forwardError();
  if (!(g->valueMin <= g->valueMax)) return makeError(file.path + ": " + g->variable + " has no valid value");
  auto transfer = volume::transferForField("auto", volume::FieldInfo{g->variable, g->units, g->standardName},
                                           std::numeric_limits<double>::quiet_NaN(),
                                           volume::ValueRange{g->valueMin, g->valueMax});
  if (!transfer) return transfer.forwardError();
  v.transfer = std::move(*transfer);
  // The variables the heights come from: named in quotes in the height note ('/orog', '/z'),
  // other than the vertical coordinate itself.
  for (std::size_t q = g->heightNote.find('\''); q != std::string::npos; q = g->heightNote.find('\'', q + 1)) {
    const std::size_t e = g->heightNote.find('\'', q + 1);
    if (e == std::string::npos) break;
    const std::string name = g->heightNote.substr(q + 1, e - q - 1);
    if (!name.empty() && name[0] == '/' && name != g->verticalVariable &&
        std::find(v.heightVariables.begin(), v.heightVariables.end(), name) == v.heightVariables.end())
      v.heightVariables.push_back(name);
    q = e;
  }
  v.grid = std::make_shared<const volume::GridVolume>(std::move(*g));
  return v;
}

std::vector<std::string> gridViewNames(const GridBenchFile& file, bool quick) {
  std::vector<std::string> names;
  if (file.key == "regional") names = {"regional-oblique", "regional-down"};
  else if (file.key == "global") names = {"global-space", "global-cyclone", "global-far"};
  else names = {file.key + "-oblique", file.key + "-down"};
  if (quick) names.resize(1);
  return names;
}

std::vector<BenchView> gridViews(const BenchVolume& v, bool quick) {
  std::vector<BenchView> views;
  for (const ViewSpec& s : viewSpecs(v)) {
    BenchView view;
    view.name = v.key + "-" + s.suffix;
    view.volume = &v;
    view.fovYDeg = s.fovYDeg;
    view.occludeByEllipsoid = true;
    if (s.down) {
      view.pose.latDeg = s.targetLatDeg;
      view.pose.lonDeg = s.targetLonDeg;
      view.pose.heightMeters = s.heightMeters;
      view.pose.headingDeg = 0.0;
      view.pose.pitchDeg = -90.0;
    } else {
      const globe::GeodesicPoint eye =
          globe::geodesicDirect(s.targetLatDeg, s.targetLonDeg, s.bearingDeg, s.distanceMeters);
      view.pose = lookAtPose({eye.latDeg, eye.lonDeg, s.heightMeters},
                             globe::geodeticToEcef({s.targetLatDeg, s.targetLonDeg, 0.0}));
    }
    views.push_back(std::move(view));
    if (quick) break;
  }
  return views;
}

volume::GridCrop visibleCrop(const engine::Camera& camera, const volume::GridVolume& g) {
  const volume::GridWindow window = engine::visibleGridWindow(camera, g);
  volume::GridCrop crop;
  if (window.empty()) {
    crop.southDeg = 1.0, crop.northDeg = -1.0;
    return crop;
  }
  const std::size_t nx = g.nx, ny = g.ny;
  const std::size_t stride = engine::visibleGridStride(g);
  const std::size_t j0 = window.firstRow, j1 = window.firstRow + window.rowCount - 1;
  double south = 90.0, north = -90.0, west = 0.0, east = 0.0;
  for (std::size_t i = 0; i < nx; i += stride)
    for (std::size_t j : {j0, j1}) south = std::min(south, g.latDegAt(j, i)), north = std::max(north, g.latDegAt(j, i));
  // A global grid's end row reaches the pole.
  if (g.wrapsLongitude && j0 == 0) south = -90.0;
  if (g.wrapsLongitude && j1 >= ny - 1 - std::min(ny - 1, stride)) north = 90.0;
  const bool allLongitudes = window.columnCount >= nx && g.wrapsLongitude;
  if (g.wrapsLongitude) {
    const double stepDeg = 360.0 / static_cast<double>(nx);
    west = g.lonDeg[window.firstColumn];  // a reduced grid: its reference axis
    east = west + static_cast<double>(window.columnCount - 1) * stepDeg;
  } else {
    const std::size_t i0 = window.firstColumn, i1 = window.firstColumn + window.columnCount - 1;
    west = 1e9, east = -1e9;
    for (std::size_t j = j0; j <= j1; j += stride)
      for (std::size_t i : {i0, i1}) {
        const double lon = g.reduced() ? g.lonDeg[i] : g.lonDegAt(j, i);  // reduced: its reference axis
        west = std::min(west, lon), east = std::max(east, lon);
      }
  }
  crop.southDeg = south;
  crop.northDeg = north;
  if (allLongitudes || south <= -90.0 || north >= 90.0) {
    crop.westDeg = -180.0, crop.eastDeg = 180.0;
  } else {
    // The reader takes longitudes in any turn; east < west means across the antimeridian.
    auto wrap = [](double x) { return x - 360.0 * std::floor((x + 180.0) / 360.0); };
    crop.westDeg = wrap(west);
    crop.eastDeg = wrap(east);
    if (crop.eastDeg == crop.westDeg) crop.eastDeg += 1e-9;
  }
  return crop;
}

Status attachCropGL(BenchView& view) {
  const BenchVolume& v = *view.volume;
  const engine::Camera camera(view.pose, view.fovYDeg, 320, 180);
  view.crop = visibleCrop(camera, *v.grid);
  volume::GridReadOptions read = v.gridRead;
  read.crop = view.crop;
  auto g = volume::readGridVolume(v.path, read);
  if (!g) return g.forwardError();
  view.cropBytesRead = g->bytesRead;
  auto gl = engine::GridVolumeGL::create(*g);
  if (!gl) return makeError(v.path + ": " + gl.error());
  view.gl = std::shared_ptr<engine::VolumeGL>(std::move(*gl));
  return Ok{};
}

std::vector<float> ellipsoidDepth(const engine::Camera& camera) {
  const int w = camera.widthPx(), h = camera.heightPx();
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  const glm::dvec3 forward = -rc.cameraToEcef[2];
  std::vector<float> depth(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::dvec3 dir = volume::pixelRayDirection(rc, x + 0.5, y + 0.5);
      const auto hit = globe::intersectRayEllipsoid(rc.eyeEcef, dir);
      if (!hit) continue;
      const double viewDistance = glm::length(*hit - rc.eyeEcef) * glm::dot(dir, forward);
      // GL row 0 is the bottom.
      depth[static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] =
          static_cast<float>(camera.nearMeters() / viewDistance);
    }
  return depth;
}

}  // namespace atmoglobe::bench
