#include <atmoglobe/bench/SceneBench.h>

#include <atmoglobe/bench/Format.h>
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/bench/Process.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/engine/ViewCulling.h>
#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/volume/AtomicFile.h>
#include <atmoglobe/volume/StationList.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>

namespace atmoglobe::bench {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

struct Site {
  const char* id;
  double latDeg, lonDeg, altitudeMslMeters;
};
// WSR-88D sites (approximate public NWS positions; used only when no station list is present).
// Order matters: the 4-radar scenes take the first four (spread over the country: the regional
// view over KTLX shows one), the 16-radar scenes all (KINX, KVNX, KFDR lie near KTLX: four in
// the regional view).
const Site kSites[] = {
    {"KTLX", 35.3331, -97.2778, 384.7}, {"KATX", 48.1947, -122.4956, 151.0},  {"KOKX", 40.8656, -72.8639, 26.0},
    {"KAMX", 25.6111, -80.4128, 4.0},   {"KINX", 36.1750, -95.5644, 204.0},   {"KVNX", 36.7406, -98.1278, 369.0},
    {"KFDR", 34.3622, -98.9764, 386.0}, {"KMUX", 37.1553, -121.8983, 1057.0}, {"KLIX", 30.3367, -89.8256, 7.0},
    {"KMPX", 44.8489, -93.5653, 288.0}, {"KLOT", 41.6047, -88.0847, 202.0},   {"KBOX", 41.9558, -71.1369, 36.0},
    {"KFSD", 43.5878, -96.7294, 436.0}, {"KCRP", 27.7842, -97.5111, 14.0},    {"KMLB", 28.1133, -80.6542, 11.0},
    {"KGGW", 48.2064, -106.6250, 694.0}};
constexpr int kSteps = 10;
constexpr std::size_t kStepsTimed = 3;

// The regional view: 800 km above KTLX looking straight down (45 deg vertical field of view:
// ~660 x 1180 km); the whole globe: 1.5e7 m above the middle of the country.
const double kRegional[6] = {35.33, -97.28, 8e5, 0.0, -90.0, 0.0};
const double kGlobe[6] = {38.0, -96.0, 1.5e7, 0.0, -90.0, 0.0};

std::vector<Site> sitePositions(const std::string& dataDir, std::ostream& log) {
  std::vector<Site> sites(std::begin(kSites), std::end(kSites));
  const fs::path dir = fs::path(dataDir) / "stations";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    log << "scenes: no " << dir.string() << ": built-in NEXRAD site positions\n";
    return sites;
  }
  std::map<std::string, volume::Station> byId;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    auto list = volume::readStationList(entry.path().string());
    if (!list) continue;
    for (const volume::Station& s : *list) byId[s.id] = s;
  }
  int found = 0;
  for (Site& s : sites)
    if (auto it = byId.find(s.id); it != byId.end()) {
      s.latDeg = it->second.latDeg, s.lonDeg = it->second.lonDeg, s.altitudeMslMeters = it->second.elevationMeters;
      ++found;
    }
  log << "scenes: " << found << " of " << sites.size() << " site positions from " << dir.string() << "\n";
  return sites;
}

double peakRssMb() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

// Table numbers: whole numbers from 100 up, else three significant digits.
std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, v >= 100.0 ? "%.0f" : "%.3g", v);
  return b;
}

std::uint64_t tallyBytes() {
  std::uint64_t sum = 0;
  for (const auto& [name, bytes] : io::netcdfReadTally()) sum += bytes;
  return sum;
}

}  // namespace

int runSceneProbe(const std::string& jobFile, const std::string& resultFile) {
  nlohmann::json job, result;
  auto finish = [&](const std::string& error) {
    if (!error.empty()) result["error"] = error;
    result["peak_rss_mb"] = peakRssMb();
    std::ofstream(resultFile) << result.dump(1);
    return error.empty() ? 0 : 1;
  };
  try {
    std::ifstream(jobFile) >> job;
  } catch (const std::exception& e) {
    return finish(jobFile + ": " + e.what());
  }
  auto context = engine::HeadlessContextGL::create();
  if (!context) return finish(context.error());
  auto loader = engine::openImagery({}, {});
  if (!loader) return finish(loader.error());
  auto renderer = engine::SceneRendererGL::create(*loader);
  if (!renderer) return finish(renderer.error());
  const auto c = job["camera"].get<std::vector<double>>();
  engine::SceneDescription scene;
  scene.camera = {c[0], c[1], c[2], c[3], c[4], c[5]};
  scene.fovYDeg = job.value("fov", 45.0);
  scene.widthPx = job.value("width", 480);
  scene.heightPx = job.value("height", 270);
  for (const auto& path : job["radars"]) {
    engine::VolumeLayerDescription d;
    d.kind = engine::VolumeKind::Radar;
    d.path = path.get<std::string>();
    d.stepMeters = 1000.0;
    scene.volumes.push_back(d);
  }
  const engine::Camera camera(scene.camera, scene.fovYDeg, scene.widthPx, scene.heightPx);
  io::resetNetcdfReadTally();
  // Load: what `render` does before its first frame (culling, then each radar read, laid out and
  // uploaded).
  const auto t0 = Clock::now();
  if (job.value("cull", true)) engine::cullRadarsOutsideView(scene, camera);
  for (const engine::VolumeLayerDescription& d : scene.volumes)
    if (auto st = (*renderer)->addVolume(d); !st) return finish(st.error());
  glFinish();
  result["load_ms"] = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  result["loaded"] = scene.volumes.size();
  result["read_bytes"] = tallyBytes();
  auto target = engine::FramebufferGL::create(scene.widthPx, scene.heightPx);
  if (!target) return finish(target.error());
  std::vector<double> frames;
  for (int f = 0; f < std::max(1, job.value("frames", 3)) + 1; ++f) {
    const auto t = Clock::now();
    auto image = (*renderer)->renderToImage(camera, {}, **target, 64, nullptr);
    if (!image) return finish(image.error());
    if (f > 0) frames.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t).count());  // 1st: warm-up
  }
  result["frame_ms"] = median(frames);
  // A time series: each change of step (the loops' next volumes read and uploaded) and a frame.
  if (job.value("steps", 1) > 1 && !scene.volumes.empty()) {
    auto axis = engine::sceneTimeAxis(**renderer);
    if (!axis) return finish(axis.error());
    std::vector<double> steps;
    // The first kStepsTimed steps (each reads every loop's volume of that time: the cost of a
    // step, the same for every step; all ten would take minutes per child for 16 radars).
    for (std::size_t s = 0; s < std::min<std::size_t>(axis->times.size(), kStepsTimed); ++s) {
      const auto t = Clock::now();
      if (auto when = engine::showSceneTime(**renderer, *axis, s); !when) return finish(when.error());
      auto image = (*renderer)->renderToImage(camera, {}, **target, 64, nullptr);
      if (!image) return finish(image.error());
      steps.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t).count());
    }
    result["step_ms"] = median(steps);
    result["steps_shown"] = steps.size();
    result["steps_in_axis"] = axis->times.size();
    result["read_bytes_all_steps"] = tallyBytes();
  }
  return finish("");
}

Result<std::vector<SceneCaseResult>> runSceneBench(const SceneBenchOptions& o, std::ostream& log) {
  const fs::path root = fs::path(o.outDir) / "scenes", data = root / "data";
  std::error_code ec;
  fs::create_directories(data, ec);
  if (ec) return makeError(data.string() + ": cannot create directory: " + ec.message());
  std::string self = o.selfExe;
  if (self.empty()) self = fs::read_symlink("/proc/self/exe", ec).string();
  // The SYNTHETIC volumes: 16 sites x 10 times (5 minutes apart, the storm moving east).
  const std::vector<Site> sites = sitePositions(o.dataDir, log);
  for (const Site& s : sites) {
    fs::create_directories(data / s.id, ec);
    for (int t = 0; t < kSteps; ++t) {
      char name[64];
      std::snprintf(name, sizeof name, "%s_%02d.nc", s.id, t);
      const fs::path file = data / s.id / name;
      if (fs::exists(file, ec)) continue;
      volume::SyntheticRadarOptions so;
      so.siteId = s.id, so.siteLatDeg = s.latDeg, so.siteLonDeg = s.lonDeg;
      so.antennaAltitudeMslMeters = s.altitudeMslMeters + 15.0;
      so.stormEastKm = -50.0 + 4.0 * t;
      char when[32];
      std::snprintf(when, sizeof when, "2020-05-01T21:%02d:00Z", 5 * t);
      so.startTimeIso8601 = when;
      so.seed = static_cast<std::uint64_t>(t + 1);
      // Half the WSR-88D's gates (500 m instead of 250 m, 14 sweeps x 360 rays x 456 gates):
      // 160 files must be written on a shared 2-core machine in minutes.
      so.gateSpacingMeters = 500.0;
      so.deflateLevel = 1;
      log << "scenes: writing " << file.string() << "\n" << std::flush;
      if (auto st = volume::writeSyntheticCfRadial(file.string(), so); !st) return st.forwardError();
    }
  }
  std::vector<SceneCaseResult> results;
  struct Case {
    int radars, steps;
    bool regional, cull;
  };
  std::vector<Case> cases;
  for (bool regional : {false, true})
    for (int n : {1, 4, 16})
      for (int steps : {1, kSteps}) cases.push_back({n, steps, regional, true});
  // The same regional scenes with every radar loaded: what culling saves.
  cases.push_back({16, 1, true, false});
  cases.push_back({16, kSteps, true, false});
  int caseIndex = 0;
  for (const Case& k : cases) {
    SceneCaseResult r;
    r.radars = k.radars, r.steps = k.steps, r.cull = k.cull;
    r.view = k.regional ? "regional" : "globe";
    r.name = std::to_string(k.radars) + " radar" + (k.radars > 1 ? "s" : "") + ", " + std::to_string(k.steps) +
             " step" + (k.steps > 1 ? "s" : "") + ", " + r.view + (k.cull ? "" : " (--load-all)");
    nlohmann::json job;
    job["radars"] = nlohmann::json::array();
    std::uintmax_t fileBytes = 0;
    for (int i = 0; i < k.radars; ++i) {
      const fs::path dir = data / sites[static_cast<std::size_t>(i)].id;
      for (int t = 0; t < k.steps; ++t) {
        char name[64];
        std::snprintf(name, sizeof name, "%s_%02d.nc", sites[static_cast<std::size_t>(i)].id, kSteps - k.steps + t);
        fileBytes += fs::file_size(dir / name, ec);
        if (k.steps == 1) job["radars"].push_back(fs::absolute(dir / name).string());
      }
      if (k.steps > 1) job["radars"].push_back(fs::absolute(dir).string());
    }
    r.fileMb = static_cast<double>(fileBytes) / 1048576.0;
    const double* cam = k.regional ? kRegional : kGlobe;
    job["camera"] = std::vector<double>(cam, cam + 6);
    job["fov"] = 45.0;
    job["width"] = o.widthPx, job["height"] = o.heightPx;
    job["frames"] = o.frames;
    job["cull"] = k.cull;
    job["steps"] = k.steps;
    const fs::path jobFile = root / ("case" + std::to_string(caseIndex) + "-job.json"),
                   resultFile = root / ("case" + std::to_string(caseIndex) + "-result.json");
    ++caseIndex;
    std::ofstream(jobFile) << job.dump(1);
    std::vector<double> load, frame, step, rss;
    log << "scenes: " << r.name << " ..." << std::flush;
    for (int run = 0; run < o.runs; ++run) {
      fs::remove(resultFile, ec);
      const ProgramExit exit = runProgram(
          {self, "bench", "--scene-probe", fs::absolute(jobFile).string(), fs::absolute(resultFile).string()}, true);
      nlohmann::json res;
      try {
        std::ifstream(resultFile) >> res;
      } catch (const std::exception& e) {
        r.error = "probe: " + exit.describe() + ": " + e.what();
        break;
      }
      if (!exit.succeeded() || res.contains("error")) {
        r.error = res.value("error", exit.describe());
        break;
      }
      load.push_back(res.value("load_ms", 0.0));
      frame.push_back(res.value("frame_ms", 0.0));
      step.push_back(res.value("step_ms", 0.0));
      rss.push_back(static_cast<double>(exit.maxRssKb) / 1024.0);
      r.loaded = res.value("loaded", 0);
      r.readMb = static_cast<double>(res.value("read_bytes", std::uint64_t{0})) / 1048576.0;
    }
    if (r.error.empty() && !load.empty()) {
      r.loadMs = median(load), r.frameMs = median(frame), r.stepMs = median(step), r.peakRssMb = median(rss);
      log << " " << r.loaded << " loaded, load " << formatG(r.loadMs, 4) << " ms, frame " << formatG(r.frameMs, 4)
          << " ms, peak " << formatG(r.peakRssMb, 4) << " MB\n";
    } else {
      log << " error: " << r.error << "\n";
    }
    results.push_back(r);
  }
  const std::string md = sceneBenchMarkdown(results, o);
  if (auto st = volume::writeFileAtomic((root / "scene-load.md").string(), md); !st) return st.forwardError();
  log << md;
  return results;
}

std::string sceneBenchMarkdown(const std::vector<SceneCaseResult>& results, const SceneBenchOptions& o) {
  std::ostringstream s;
  s << "| scene | view | radars loaded | files on disk (MB) | field data read (MB) | load (ms) | frame (ms) | "
       "time step (ms) | peak RSS (MB) |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const SceneCaseResult& r : results) {
    if (!r.error.empty()) {
      s << "| " << r.name << " | " << r.view << " | error: " << r.error << " |||||||\n";
      continue;
    }
    s << "| " << r.radars << " x " << r.steps << (r.cull ? "" : " (--load-all)") << " | " << r.view << " | " << r.loaded
      << " of " << r.radars << " | " << num(r.fileMb) << " | " << num(r.readMb) << " | " << num(r.loadMs) << " | "
      << num(r.frameMs) << " | " << (r.steps > 1 ? num(r.stepMs) : std::string("-")) << " | " << num(r.peakRssMb)
      << " |\n";
  }
  s << "\nMedians of " << o.runs << " child processes per scene (frame: median of " << o.frames
    << " frames after one warm-up, " << o.widthPx << "x" << o.heightPx << ", step 1000 m; time step: median of the "
    << "first " << kStepsTimed << " steps of the loops, each the step's volumes read and uploaded plus a frame).\n";
  return s.str();
}

}  // namespace atmoglobe::bench
