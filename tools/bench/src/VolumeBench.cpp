#include <atmoglobe/bench/VolumeBench.h>

#include <atmoglobe/bench/Cells.h>
#include <atmoglobe/bench/Format.h>
#include <atmoglobe/bench/GridLoad.h>
#include <atmoglobe/bench/GridViews.h>
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
#include <atmoglobe/globe/Progress.h>
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

/// Every --view name must be one of `known` (checked before anything is loaded); `what` names
/// the views in the message ("views", "grid views").
Status checkViewNames(const VolumeBenchOptions& o, const std::vector<std::string>& known, const std::string& what) {
  for (const std::string& name : o.viewNames) {
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const std::string& k : known) list.append(list.empty() ? "" : ", ").append(k);
      return makeError("--view " + name + ": no such view (" + what + (o.quick ? " with --quick" : "") + ": " + list +
                       ")");
    }
  }
  return Ok{};
}

/// The GL side of a bench run: a headless context and the marcher (none with --reference-only:
/// no GL at all, e.g. filling the reference cache on a many-core machine).
struct BenchGL {
  std::unique_ptr<engine::HeadlessContextGL> context;
  std::unique_ptr<engine::VolumeRendererGL> renderer;
  std::string name = "none";
};
Result<BenchGL> openBenchGL(const VolumeBenchOptions& o) {
  BenchGL gl;
  if (o.referenceOnly) return gl;
  auto c = engine::HeadlessContextGL::create();
  if (!c) return c.forwardError();
  gl.context = std::move(*c);
  gl.name = gl.context->describe();
  auto r = engine::VolumeRendererGL::create();
  if (!r) return r.forwardError();
  gl.renderer = std::move(*r);
  return gl;
}

}  // namespace

Result<VolumeBenchOutcome> runVolumeBench(const VolumeBenchOptions& o, std::ostream& log) {
  if (o.grids || !o.gridFile.empty()) return runGridBench(o, log);
  const auto tStart = Clock::now();
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::error_code ec;
  fs::create_directories(fs::path(o.outDir) / "reference-cache", ec);
  if (ec) return makeError(o.outDir + ": cannot create directory: " + ec.message());

  // The volumes and their views; --view names are checked before anything is loaded.
  const std::vector<BenchFile> files = benchFiles(o.quick);
  const std::vector<std::string> knownViews = benchViewNames(files, o.quick);
  if (Status st = checkViewNames(o, knownViews, "views"); !st) return st.forwardError();
  auto wanted = [&](const std::string& view) {
    return o.viewNames.empty() || std::find(o.viewNames.begin(), o.viewNames.end(), view) != o.viewNames.end();
  };

  auto benchGL = openBenchGL(o);
  if (!benchGL) return benchGL.forwardError();
  engine::VolumeRendererGL* renderer = benchGL->renderer.get();
  const std::string& glName = benchGL->name;

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
  globe::Progress progress("bench views", views.size());  // stderr; the log is stdout
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
      r.gpuBytes = view.volume->gl->gpuBytes();
      report.rows.push_back(r);
      if (isEngineDefault(c)) {
        const std::string png = (fs::path(o.outDir) / (view.name + "-gpu-" + modeName(c.mode) + ".png")).string();
        if (auto s = globe::writePng(png, runs[ci].image); !s) return s.forwardError();
      }
    }
    progress.advance(1, view.name);
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

Result<VolumeBenchOutcome> runGridBench(const VolumeBenchOptions& o, std::ostream& log) {
  const auto tStart = Clock::now();
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::error_code ec;
  fs::create_directories(fs::path(o.outDir) / "reference-cache", ec);
  if (ec) return makeError(o.outDir + ": cannot create directory: " + ec.message());

  std::vector<GridBenchFile> files;
  if (o.gridFile.empty()) {
    files = builtinGridFiles(fs::path(o.outDir) / "grids");
  } else {
    files.push_back({fs::path(o.gridFile).stem().string(), o.gridFile, o.gridVariable, o.gridTimeIndex, false});
  }
  std::vector<std::string> knownViews;
  for (const GridBenchFile& f : files)
    for (const std::string& n : gridViewNames(f, o.quick)) knownViews.push_back(n);
  if (Status st = checkViewNames(o, knownViews, "grid views"); !st) return st.forwardError();
  auto wanted = [&](const std::string& view) {
    return o.viewNames.empty() || std::find(o.viewNames.begin(), o.viewNames.end(), view) != o.viewNames.end();
  };

  auto benchGL = openBenchGL(o);
  if (!benchGL) return benchGL.forwardError();
  engine::VolumeRendererGL* renderer = benchGL->renderer.get();
  const std::string& glName = benchGL->name;

  std::vector<std::unique_ptr<BenchVolume>> volumes;
  std::vector<BenchView> views;
  for (const GridBenchFile& file : files) {
    const std::vector<std::string> names = gridViewNames(file, o.quick);
    if (std::none_of(names.begin(), names.end(), wanted)) continue;
    if (Status st = ensureGridFile(file, log); !st) return st.forwardError();
    auto v = loadGridBenchVolume(file);
    if (!v) return v.forwardError();
    volumes.push_back(std::make_unique<BenchVolume>(std::move(*v)));
    const BenchVolume& bv = *volumes.back();
    log << bv.key << ": " << bv.path << ", " << bv.grid->variable << " at " << bv.grid->validTime << ", " << bv.grid->nx
        << " x " << bv.grid->ny << " x " << bv.grid->nz << "\n";
    for (BenchView& view : gridViews(bv, o.quick)) {
      if (!wanted(view.name)) continue;
      if (!o.referenceOnly) {
        if (Status st = attachCropGL(view); !st) return st.forwardError();
        log << "  view " << view.name << ": crop lat " << formatG(view.crop.southDeg, 5) << ".."
            << formatG(view.crop.northDeg, 5) << ", lon " << formatG(view.crop.westDeg, 5) << ".."
            << formatG(view.crop.eastDeg, 5) << ", " << formatG(static_cast<double>(view.cropBytesRead) / 1e6, 4)
            << " MB read, GPU " << formatG(static_cast<double>(view.gl->gpuBytes()) / 1e6, 4) << " MB\n";
      }
      views.push_back(std::move(view));
    }
  }

  const int w = o.quick ? 160 : 320, h = o.quick ? 90 : 180;
  const int bw = 1280, bh = 720;
  const std::vector<Cell> cells = gridCells(standardAxes(o.quick, o.stepsMeters), false);
  // At 1280x720: DVR, linear, point classification, the bench's steps among {250, 1000} m (the
  // default and the interactive one) at every scale.
  std::vector<Cell> bigCells;
  for (const Cell& c : cells)
    if (c.mode == volume::VolumeRenderMode::Dvr && c.interpolation == volume::Interpolation::Linear &&
        c.classification == engine::Classification::Point && (c.stepMeters == 250.0 || c.stepMeters == 1000.0) &&
        (!o.quick || isEngineDefault(c)))
      bigCells.push_back(c);

  ReferenceStore refs;
  refs.dir = fs::path(o.outDir) / "reference-cache";
  refs.threads = threads;
  refs.log = &log;
  auto settingsFor = [&](const BenchView& view, volume::VolumeRenderMode mode, double step) {
    return referenceSettings(mode, step, view.volume->transfer);
  };

  if (o.referenceOnly) {
    for (const BenchView& view : views) {
      for (auto mode : kModes) refs.get(view, w, h, settingsFor(view, mode, o.referenceStepMeters));
      if (o.big && !bigCells.empty())
        refs.get(view, bw, bh, settingsFor(view, volume::VolumeRenderMode::Dvr, o.referenceStepMeters));
      if (!o.quick) {
        refs.get(view, 80, 45, settingsFor(view, volume::VolumeRenderMode::Dvr, o.referenceStepMeters));
        refs.get(view, 80, 45, settingsFor(view, volume::VolumeRenderMode::Dvr, o.referenceStepMeters / 2.0));
      }
    }
    log << "references: " << refs.rendered << " rendered (" << refs.secondsRendering << " s), " << refs.cached
        << " cached, in " << refs.dir.string() << "\n";
    return VolumeBenchOutcome{};
  }

  BenchReport report;
  report.kind = "grid";
  report.machine = machineLine(glName);
  report.widthPx = w, report.heightPx = h;
  report.frames = o.frames;
  report.referenceStepMeters = o.referenceStepMeters;
  report.views = views;
  for (const auto& v : volumes) {
    VolumeSummary s;
    s.key = v->key;
    s.path = v->path;
    s.fieldName = v->grid->variable + " at " + v->grid->validTime + " (" + std::to_string(v->grid->nx) + " x " +
                  std::to_string(v->grid->ny) + " x " + std::to_string(v->grid->nz) + ", " + v->grid->heightNote + ")";
    s.sweeps = v->grid->nz;
    report.volumes.push_back(s);
  }

  // Load: each case in a child process (its own peak memory).
  if (o.load) {
    std::string self = o.selfExe;
    if (self.empty()) self = fs::read_symlink("/proc/self/exe", ec).string();
    for (const auto& v : volumes) {
      std::vector<LoadCase> c = measureGridLoads(*v, views, self, o.outDir, o.loadRuns, log);
      report.loads.insert(report.loads.end(), c.begin(), c.end());
    }
  }

  auto target = engine::FramebufferGL::create(w, h);
  if (!target) return target.forwardError();
  globe::Progress progress("bench views", views.size());  // stderr; the log is stdout
  for (const BenchView& view : views) {
    log << "view " << view.name << " (" << w << "x" << h << ")\n";
    const engine::Camera camera(view.pose, view.fovYDeg, w, h);
    const std::vector<float> depth = ellipsoidDepth(camera);
    std::map<volume::VolumeRenderMode, volume::VolumeImage> ref;
    for (auto mode : kModes) {
      ref[mode] = refs.get(view, w, h, settingsFor(view, mode, o.referenceStepMeters));
      const std::string png = (fs::path(o.outDir) / (view.name + "-reference-" + modeName(mode) + ".png")).string();
      if (auto s = globe::writePng(png, toRgba8(ref[mode])); !s) return s.forwardError();
    }
    std::vector<GpuRun> runs = timeCellsRoundRobinGL(*renderer, camera, *view.glVolume(), cells, **target, o.frames,
                                                     &depth, &view.volume->transfer);
    for (std::size_t ci = 0; ci < cells.size(); ++ci) {
      Row r;
      r.view = view.name;
      r.volume = view.volume->key;
      r.cell = cells[ci];
      r.widthPx = w, r.heightPx = h;
      r.medianMs = runs[ci].medianMs;
      r.error = volume::compareImages(fromRgba8(runs[ci].image), ref[cells[ci].mode]);
      r.gpuBytes = view.glVolume()->gpuBytes();
      report.rows.push_back(r);
      if (isEngineDefault(cells[ci])) {
        const std::string png =
            (fs::path(o.outDir) / (view.name + "-gpu-" + modeName(cells[ci].mode) + ".png")).string();
        if (auto s = globe::writePng(png, runs[ci].image); !s) return s.forwardError();
      }
    }
    progress.advance(1, view.name);
  }

  if (o.big && !bigCells.empty()) {
    auto bigTarget = engine::FramebufferGL::create(bw, bh);
    if (!bigTarget) return bigTarget.forwardError();
    for (const BenchView& view : views) {
      log << "view " << view.name << " (" << bw << "x" << bh << ")\n";
      const engine::Camera camera(view.pose, view.fovYDeg, bw, bh);
      const std::vector<float> depth = ellipsoidDepth(camera);
      const volume::VolumeImage ref =
          refs.get(view, bw, bh, settingsFor(view, volume::VolumeRenderMode::Dvr, o.referenceStepMeters));
      std::vector<GpuRun> runs = timeCellsRoundRobinGL(*renderer, camera, *view.glVolume(), bigCells, **bigTarget,
                                                       std::min(o.frames, 3), &depth, &view.volume->transfer);
      for (std::size_t ci = 0; ci < bigCells.size(); ++ci) {
        Row r;
        r.view = view.name;
        r.volume = view.volume->key;
        r.cell = bigCells[ci];
        r.widthPx = bw, r.heightPx = bh;
        r.medianMs = runs[ci].medianMs;
        r.error = volume::compareImages(fromRgba8(runs[ci].image), ref);
        r.gpuBytes = view.glVolume()->gpuBytes();
        report.bigRows.push_back(r);
        if (isEngineDefault(bigCells[ci])) {
          const std::string png = (fs::path(o.outDir) / (view.name + "-1280-gpu-dvr.png")).string();
          if (auto s = globe::writePng(png, runs[ci].image); !s) return s.forwardError();
          const std::string rpng = (fs::path(o.outDir) / (view.name + "-1280-reference-dvr.png")).string();
          if (auto s = globe::writePng(rpng, toRgba8(ref)); !s) return s.forwardError();
        }
      }
    }
  }

  for (const BenchView& view : views) {
    if (o.quick) break;
    const volume::VolumeImage a =
        refs.get(view, 80, 45, settingsFor(view, volume::VolumeRenderMode::Dvr, o.referenceStepMeters));
    const volume::VolumeImage b =
        refs.get(view, 80, 45, settingsFor(view, volume::VolumeRenderMode::Dvr, o.referenceStepMeters / 2.0));
    report.convergence.push_back({view.name, volume::compareImages(a, b)});
  }
  report.aggregates = aggregate(report.rows, cells);

  if (!o.peer) {
    report.peer.note = "peer skipped (--no-peer)";
  } else {
    PeerSettings ps;
    ps.outDir = o.outDir;
    ps.script = findPeerScript(o.peerScript);
    ps.widthPx = w, ps.heightPx = h;
    ps.frames = o.frames;
    ps.maxVoxels = o.quick ? 3.2e7 : o.gridPeerMaxVoxels;
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
