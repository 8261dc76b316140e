#include <atmoglobe/bench/VolumeBench.h>

#include <atmoglobe/bench/Cells.h>
#include <atmoglobe/bench/Format.h>
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/bench/ReferenceCache.h>
#include <atmoglobe/bench/Report.h>
#include <atmoglobe/bench/Views.h>
#include <atmoglobe/bench/VtkPeer.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <ostream>
#include <thread>

namespace atmoglobe::bench {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr volume::VolumeRenderMode kModes[] = {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip,
                                               volume::VolumeRenderMode::Iso};

}  // namespace

Result<VolumeBenchOutcome> runVolumeBench(const VolumeBenchOptions& o, std::ostream& log) {
  const auto tStart = Clock::now();
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::error_code ec;
  fs::create_directories(fs::path(o.outDir) / "reference-cache", ec);
  if (ec) return makeError(o.outDir + ": cannot create directory: " + ec.message());

  // The volumes and their views; --view names are checked before anything is loaded.
  const std::vector<BenchFile> files = benchFiles(o.quick);
  const std::vector<std::string> knownViews = benchViewNames(files, o.quick);
  for (const std::string& name : o.viewNames) {
    if (std::find(knownViews.begin(), knownViews.end(), name) == knownViews.end()) {
      std::string known;
      for (const std::string& k : knownViews) known.append(known.empty() ? "" : ", ").append(k);
      return makeError("--view " + name + ": no such view (views" + (o.quick ? " with --quick" : "") + ": " + known +
                       ")");
    }
  }
  auto wanted = [&](const std::string& view) {
    return o.viewNames.empty() || std::find(o.viewNames.begin(), o.viewNames.end(), view) != o.viewNames.end();
  };

  // --reference-only: no GL at all (fills the reference cache, e.g. on a many-core machine).
  std::unique_ptr<engine::HeadlessContextGL> context;
  std::unique_ptr<engine::VolumeRendererGL> renderer;
  std::string glName = "none";
  if (!o.referenceOnly) {
    auto c = engine::HeadlessContextGL::create();
    if (!c) return c.forwardError();
    context = std::move(*c);
    glName = context->describe();
    auto r = engine::VolumeRendererGL::create();
    if (!r) return r.forwardError();
    renderer = std::move(*r);
  }

  // Volumes (only those a chosen view shows).
  std::vector<std::unique_ptr<BenchVolume>> volumes;
  for (const BenchFile& file : files) {
    if (!wanted(file.key + "-oblique") && !wanted(file.key + "-down")) continue;
    const std::string path = (fs::path(o.dataDir) / file.relativePath).string();
    auto v = loadBenchVolume(file.key, path);
    if (!v) return v.forwardError();
    if (!o.referenceOnly) {
      auto gl = engine::RadarVolumeGL::create(v->polar);
      if (!gl) return makeError(path + ": " + gl.error());
      v->gl = std::move(*gl);
    }
    volumes.push_back(std::make_unique<BenchVolume>(std::move(*v)));
    log << file.key << ": " << path << ", field " << volumes.back()->polar.fieldName << ", "
        << volumes.back()->polar.sweeps.size() << " sweeps\n";
  }

  std::vector<BenchView> views = standardViews(volumes, o.quick);
  std::erase_if(views, [&](const BenchView& v) { return !wanted(v.name); });

  // The grid.
  const int w = o.quick ? 160 : 320, h = o.quick ? 90 : 180;
  const std::vector<Cell> cells = gridCells(standardAxes(o.quick, o.stepsMeters));

  ReferenceStore refs;
  refs.dir = fs::path(o.outDir) / "reference-cache";
  refs.threads = threads;
  refs.log = &log;

  if (o.referenceOnly) {
    for (const BenchView& view : views) {
      for (auto mode : kModes) refs.get(view, w, h, referenceSettings(mode, o.referenceStepMeters));
      if (!o.quick) {
        refs.get(view, 80, 45, referenceSettings(volume::VolumeRenderMode::Dvr, o.referenceStepMeters));
        refs.get(view, 80, 45, referenceSettings(volume::VolumeRenderMode::Dvr, o.referenceStepMeters / 2.0));
      }
    }
    log << "references: " << refs.rendered << " rendered (" << refs.secondsRendering << " s), " << refs.cached
        << " cached, in " << refs.dir.string() << "\n";
    return VolumeBenchOutcome{};
  }

  BenchReport report;
  report.machine = machineLine(glName);
  report.widthPx = w, report.heightPx = h;
  report.frames = o.frames;
  report.referenceStepMeters = o.referenceStepMeters;
  for (const auto& v : volumes) {
    report.volumes.push_back({v->key, v->path, v->polar.fieldName, v->polar.sweeps.size(), v->gl->gpuBytes(),
                              volume::cartesianEquivalentBytes(v->polar, 4.0)});
  }
  report.views = views;

  auto target = engine::FramebufferGL::create(w, h);
  if (!target) return target.forwardError();
  for (const BenchView& view : views) {
    log << "view " << view.name << " (" << w << "x" << h << ")\n";
    const engine::Camera camera(view.pose, view.fovYDeg, w, h);
    std::map<volume::VolumeRenderMode, volume::VolumeImage> ref;
    for (auto mode : kModes) {
      ref[mode] = refs.get(view, w, h, referenceSettings(mode, o.referenceStepMeters));
      const std::string png = (fs::path(o.outDir) / (view.name + "-reference-" + modeName(mode) + ".png")).string();
      if (auto s = globe::writePng(png, toRgba8(ref[mode])); !s) return s.forwardError();
    }
    std::vector<GpuRun> runs = timeCellsRoundRobinGL(*renderer, camera, *view.volume->gl, cells, **target, o.frames);
    for (std::size_t ci = 0; ci < cells.size(); ++ci) {
      const Cell& c = cells[ci];
      Row r;
      r.view = view.name;
      r.volume = view.volume->key;
      r.cell = c;
      r.widthPx = w, r.heightPx = h;
      r.medianMs = runs[ci].medianMs;
      r.error = volume::compareImages(fromRgba8(runs[ci].image), ref[c.mode]);
      report.rows.push_back(r);
      if (isEngineDefault(c)) {
        const std::string png = (fs::path(o.outDir) / (view.name + "-gpu-" + modeName(c.mode) + ".png")).string();
        if (auto s = globe::writePng(png, runs[ci].image); !s) return s.forwardError();
      }
    }
  }

  // The default at 1280x720 (time only: a reference at that size would take ~15x longer).
  {
    auto bigTarget = engine::FramebufferGL::create(1280, 720);
    if (!bigTarget) return bigTarget.forwardError();
    // On a software rasteriser (llvmpipe) one 1280x720 frame takes minutes: time the first view
    // only, with one frame.
    const bool software = glName.find("llvmpipe") != std::string::npos || glName.find("softpipe") != std::string::npos;
    for (const BenchView& view : views) {
      const engine::Camera camera(view.pose, view.fovYDeg, 1280, 720);
      const GpuRun run = timeFramesGL(*renderer, camera, *view.volume->gl, optionsFor(Cell{}), Cell{}.beam, **bigTarget,
                                      software ? 1 : o.frames, !software);
      report.big.push_back({view.name + (software ? " (1 frame, software GL)" : ""), run.medianMs});
      if (software) break;
    }
  }

  // Reference convergence: the reference step against half of it, on a small image.
  for (const BenchView& view : views) {
    if (o.quick) break;
    const int cw = 80, ch = 45;
    const volume::VolumeImage a =
        refs.get(view, cw, ch, referenceSettings(volume::VolumeRenderMode::Dvr, o.referenceStepMeters));
    const volume::VolumeImage b =
        refs.get(view, cw, ch, referenceSettings(volume::VolumeRenderMode::Dvr, o.referenceStepMeters / 2.0));
    report.convergence.push_back({view.name, volume::compareImages(a, b)});
  }

  report.aggregates = aggregate(report.rows, cells);

  // The peer (its DVR references at the same size come from the cache filled above).
  if (!o.peer) {
    report.peer.note = "peer skipped (--no-peer)";
  } else {
    PeerSettings ps;
    ps.outDir = o.outDir;
    ps.script = findPeerScript(o.peerScript);
    ps.widthPx = w, ps.heightPx = h;
    ps.frames = o.frames;
    ps.maxVoxels = o.quick ? 3.2e7 : 2.7e8;
    ps.threads = threads;
    ps.referenceStepMeters = o.referenceStepMeters;
    Result<PeerSection> peer = runVtkPeer(volumes, views, ps, refs, log);
    if (!peer) return peer.forwardError();
    report.peer = std::move(*peer);
  }

  report.referencesRendered = refs.rendered;
  report.referencesCached = refs.cached;
  report.referenceThreads = threads;
  report.referenceSeconds = refs.secondsRendering;
  report.referenceCacheDir = refs.dir.string();
  report.totalSeconds = std::chrono::duration<double>(Clock::now() - tStart).count();
  VolumeBenchOutcome outcome;
  if (Status s = writeReport(o.outDir, report, &outcome.files); !s) return s.forwardError();
  outcome.peerNote = report.peer.note;
  return outcome;
}

}  // namespace atmoglobe::bench
