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
#include <atmoglobe/engine/GridSourceGL.h>
#include <atmoglobe/engine/GridVolumeGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/Progress.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <functional>
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

/// What differs between the kinds of volume: which volumes and views, which cells, what is
/// measured at 1280x720, and the peer's cap. Everything after loading is one loop over `views`.
struct BenchPlan {
  std::string kind = "radar";  ///< the report's kind (volume_bench.* or grid_bench.*)
  std::vector<std::unique_ptr<BenchVolume>> volumes;
  std::vector<BenchView> views;
  std::vector<Cell> cells;
  /// At 1280x720, each against the reference at that size. Empty: the engine default is timed
  /// only (a radar reference at 1280x720 takes ~15x the bench size's).
  std::vector<Cell> bigCells;
  double peerMaxVoxels = 2.7e8;
  std::vector<VolumeSummary> summaries;
};

bool isGridRun(const VolumeBenchOptions& o) { return o.grids || !o.gridFile.empty(); }

std::vector<GridBenchFile> gridFilesOf(const VolumeBenchOptions& o) {
  if (!o.gridFile.empty())
    return {{fs::path(o.gridFile).stem().string(), o.gridFile, o.gridVariable, o.gridTimeIndex, o.gridMember, false}};
  return builtinGridFiles(fs::path(o.outDir) / "grids");
}

/// Every view name of the run (what --view may name), before anything is loaded.
std::vector<std::string> knownViewNames(const VolumeBenchOptions& o) {
  if (!isGridRun(o)) return benchViewNames(benchFiles(o.quick), o.quick);
  std::vector<std::string> names;
  for (const GridBenchFile& f : gridFilesOf(o))
    for (const std::string& n : gridViewNames(f, o.quick)) names.push_back(n);
  return names;
}

using WantedView = std::function<bool(const std::string&)>;

/// Radar volumes (those a chosen view shows), uploaded whole; the standard views.
Result<BenchPlan> planRadars(const VolumeBenchOptions& o, const WantedView& wanted, std::ostream& log) {
  BenchPlan plan;
  for (const BenchFile& file : benchFiles(o.quick)) {
    if (!wanted(file.key + "-oblique") && !wanted(file.key + "-down")) continue;
    const std::string path = (fs::path(o.dataDir) / file.relativePath).string();
    auto v = loadBenchVolume(file.key, path);
    if (!v) return v.forwardError();
    if (!o.referenceOnly) {
      auto gl = engine::RadarVolumeGL::create(v->polar);
      if (!gl) return makeError(path + ": " + gl.error());
      v->gl = std::move(*gl);
    }
    plan.volumes.push_back(std::make_unique<BenchVolume>(std::move(*v)));
    const BenchVolume& bv = *plan.volumes.back();
    log << bv.key << ": " << path << ", field " << bv.polar.fieldName << ", " << bv.polar.sweeps.size() << " sweeps\n";
    plan.summaries.push_back({bv.key, bv.path, bv.polar.fieldName, bv.polar.sweeps.size(),
                              bv.gl ? bv.gl->gpuBytes() : 0, volume::cartesianEquivalentBytes(bv.polar, 4.0)});
  }
  plan.views = standardViews(plan.volumes, o.quick);
  std::erase_if(plan.views, [&](const BenchView& v) { return !wanted(v.name); });
  // The step rule at 1 and 2 samples per cell beside every fixed step (scale 1, linear, 4/3 beam).
  plan.cells = gridCells(standardAxes(o.quick, o.stepsMeters), true, {1.0, 2.0});
  return plan;
}

/// Grids (the built-in ones or a file), whole for the reference; each view uploads its crop.
Result<BenchPlan> planGrids(const VolumeBenchOptions& o, const WantedView& wanted, std::ostream& log) {
  BenchPlan plan;
  plan.kind = "grid";
  plan.peerMaxVoxels = o.gridPeerMaxVoxels;
  for (const GridBenchFile& file : gridFilesOf(o)) {
    const std::vector<std::string> names = gridViewNames(file, o.quick);
    if (std::none_of(names.begin(), names.end(), wanted)) continue;
    if (Status st = ensureGridFile(file, log); !st) return st.forwardError();
    auto v = loadGridBenchVolume(file);
    if (!v) return v.forwardError();
    plan.volumes.push_back(std::make_unique<BenchVolume>(std::move(*v)));
    const BenchVolume& bv = *plan.volumes.back();
    const volume::GridVolume& g = *bv.grid;
    log << bv.key << ": " << bv.path << ", " << g.variable << " at " << g.validTime
        << (g.member >= 0 ? ", member " + std::to_string(g.member) : std::string()) << ", " << g.nx << " x " << g.ny
        << " x " << g.nz << "\n";
    VolumeSummary s;
    s.key = bv.key;
    s.path = bv.path;
    s.fieldName = g.variable + " at " + g.validTime + " (" + std::to_string(g.nx) + " x " + std::to_string(g.ny) +
                  " x " + std::to_string(g.nz) + ", " + g.heightNote + ")";
    s.sweeps = g.nz;
    plan.summaries.push_back(s);
    for (BenchView& view : gridViews(bv, o.quick)) {
      if (!wanted(view.name)) continue;
      if (!o.referenceOnly) {
        if (Status st = attachCropGL(view); !st) return st.forwardError();
        log << "  view " << view.name << ": crop lat " << formatG(view.crop.southDeg, 5) << ".."
            << formatG(view.crop.northDeg, 5) << ", lon " << formatG(view.crop.westDeg, 5) << ".."
            << formatG(view.crop.eastDeg, 5) << ", " << formatG(static_cast<double>(view.cropBytesRead) / 1e6, 4)
            << " MB read, GPU " << formatG(static_cast<double>(view.gl->gpuBytes()) / 1e6, 4) << " MB\n";
      }
      plan.views.push_back(std::move(view));
    }
  }
  // The step rule at 1 and 2 samples per cell beside every fixed step (scale 1, linear).
  plan.cells = gridCells(standardAxes(o.quick, o.stepsMeters), false, {1.0, 2.0});
  // At 1280x720: DVR, linear, point classification, the bench's steps among {250, 1000} m (the
  // default and the interactive one) at every scale, and the step rule from 250 m.
  if (o.big)
    for (const Cell& c : plan.cells)
      if (c.mode == volume::VolumeRenderMode::Dvr && c.interpolation == volume::Interpolation::Linear &&
          c.classification == engine::Classification::Point && (c.stepMeters == 250.0 || c.stepMeters == 1000.0) &&
          (c.samplesPerCell == 0.0 || c.stepMeters == 250.0) &&
          (!o.quick || isEngineDefault(c) || c.samplesPerCell > 0.0))
        plan.bigCells.push_back(c);
  return plan;
}

constexpr int kBigWidthPx = 1280, kBigHeightPx = 720;

Status writePngTo(const VolumeBenchOptions& o, const std::string& name, const globe::ImageRGBA8& image) {
  return globe::writePng((fs::path(o.outDir) / name).string(), image);
}

/// Rows of `cells` timed on `view` at `target`'s size, each against `refFor(cell)`; the engine
/// default's frame written as `pngFor(cell)`.
template <class RefFor, class PngFor>
Status measureView(const VolumeBenchOptions& o, engine::VolumeRendererGL& renderer, const BenchView& view,
                   const std::vector<Cell>& cells, engine::FramebufferGL& target, int frames, RefFor refFor,
                   PngFor pngFor, std::vector<Row>& rows) {
  const int w = target.widthPx(), h = target.heightPx();
  const engine::Camera camera(view.pose, view.fovYDeg, w, h);
  const std::vector<float> depth = view.occludeByEllipsoid ? ellipsoidDepth(camera) : std::vector<float>{};
  std::vector<GpuRun> runs = timeCellsRoundRobinGL(renderer, camera, *view.glVolume(), cells, target, frames,
                                                   depth.empty() ? nullptr : &depth, &view.volume->transfer);
  for (std::size_t ci = 0; ci < cells.size(); ++ci) {
    Row r;
    r.view = view.name;
    r.volume = view.volume->key;
    r.cell = cells[ci];
    r.widthPx = w, r.heightPx = h;
    r.medianMs = runs[ci].medianMs;
    r.error = volume::compareImages(fromRgba8(runs[ci].image), refFor(cells[ci]));
    r.gpuBytes = view.glVolume()->gpuBytes();
    rows.push_back(r);
    if (isEngineDefault(cells[ci]))
      if (Status s = writePngTo(o, pngFor(cells[ci]), runs[ci].image); !s) return s;
  }
  return Ok{};
}

/// The reference of `big` (4 x 4 rays a pixel) averaged down to a quarter of its size.
volume::VolumeImage averageDown4(const volume::VolumeImage& big) {
  volume::VolumeImage out;
  out.widthPx = big.widthPx / 4;
  out.heightPx = big.heightPx / 4;
  out.rgbaPremultiplied.assign(static_cast<std::size_t>(out.widthPx) * static_cast<std::size_t>(out.heightPx),
                               glm::dvec4(0.0));
  for (int y = 0; y < out.heightPx; ++y)
    for (int x = 0; x < out.widthPx; ++x) {
      glm::dvec4 sum(0.0);
      for (int dy = 0; dy < 4; ++dy)
        for (int dx = 0; dx < 4; ++dx) sum += big.at(4 * x + dx, 4 * y + dy);
      out.rgbaPremultiplied[static_cast<std::size_t>(y) * static_cast<std::size_t>(out.widthPx) +
                            static_cast<std::size_t>(x)] = sum / 16.0;
    }
  return out;
}

/// Grids: the engine default setting on the level of detail the engine picks for this view and
/// size (GridSourceGL::chooseDetail), when it is not the grid itself, and on the grid itself
/// beside it, against `ref` and against what `average` gives (the 4 x 4 reference), if anything.
Status measureDetail(engine::VolumeRendererGL& renderer, const BenchView& view, const std::vector<Cell>& cells,
                     engine::FramebufferGL& target, int frames, const volume::VolumeImage& ref,
                     const std::function<std::optional<volume::VolumeImage>()>& average, std::vector<Row>& rows) {
  auto* grid = dynamic_cast<engine::GridVolumeGL*>(view.glVolume());
  const auto def = std::find_if(cells.begin(), cells.end(), [](const Cell& c) {
    return c.mode == volume::VolumeRenderMode::Dvr && isEngineDefault(c);
  });
  if (!grid || def == cells.end()) return Ok{};
  const int w = target.widthPx(), h = target.heightPx();
  const engine::Camera camera(view.pose, view.fovYDeg, w, h);
  const int level = engine::gridDetailLevelFor(*grid, camera, def->imageScale);
  if (level == 0) return Ok{};
  auto coarse = engine::createGridDetail(grid->grid(), level);
  if (!coarse) return coarse.forwardError();
  const std::optional<volume::VolumeImage> averaged = average();
  const std::vector<float> depth = view.occludeByEllipsoid ? ellipsoidDepth(camera) : std::vector<float>{};
  // The two volumes frame by frame in turn (each frame after its own untimed one): a slow spell
  // of the shared machine lands on both alike.
  const std::array<engine::VolumeGL*, 2> volumes{grid, coarse->get()};
  std::array<std::vector<double>, 2> times;
  std::array<GpuRun, 2> last;
  for (int f = 0; f < frames; ++f)
    for (std::size_t v = 0; v < 2; ++v) {
      last[v] = timeCellsRoundRobinGL(renderer, camera, *volumes[v], {*def}, target, 1,
                                      depth.empty() ? nullptr : &depth, &view.volume->transfer)[0];
      times[v].push_back(last[v].medianMs);
    }
  for (std::size_t v = 0; v < 2; ++v) {
    engine::VolumeGL* volume = volumes[v];
    std::vector<GpuRun> runs{last[v]};
    std::sort(times[v].begin(), times[v].end());
    runs[0].medianMs = times[v][times[v].size() / 2];
    Row r;
    r.view = view.name;
    r.volume = view.volume->key;
    r.cell = *def;
    r.widthPx = w, r.heightPx = h;
    r.medianMs = runs[0].medianMs;
    r.error = volume::compareImages(fromRgba8(runs[0].image), ref);
    if (averaged) r.pixelAverageError = volume::compareImages(fromRgba8(runs[0].image), *averaged);
    r.gpuBytes = volume->gpuBytes();
    r.detailLevel = volume == grid ? 0 : level;
    rows.push_back(r);
  }
  return Ok{};
}

}  // namespace

Result<VolumeBenchOutcome> runVolumeBench(const VolumeBenchOptions& o, std::ostream& log) {
  const auto tStart = Clock::now();
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::error_code ec;
  fs::create_directories(fs::path(o.outDir) / "reference-cache", ec);
  if (ec) return makeError(o.outDir + ": cannot create directory: " + ec.message());

  // --view names are checked before anything is loaded.
  const bool grids = isGridRun(o);
  if (Status st = checkViewNames(o, knownViewNames(o), grids ? "grid views" : "views"); !st) return st.forwardError();
  const WantedView wanted = [&](const std::string& view) {
    return o.viewNames.empty() || std::find(o.viewNames.begin(), o.viewNames.end(), view) != o.viewNames.end();
  };
  auto benchGL = openBenchGL(o);
  if (!benchGL) return benchGL.forwardError();
  const std::string& glName = benchGL->name;
  Result<BenchPlan> loaded = grids ? planGrids(o, wanted, log) : planRadars(o, wanted, log);
  if (!loaded) return loaded.forwardError();
  BenchPlan& plan = *loaded;
  const std::vector<BenchView>& views = plan.views;

  const int w = o.widthPx > 0 ? o.widthPx : (o.quick ? 160 : 320);
  const int h = o.heightPx > 0 ? o.heightPx : (o.quick ? 90 : 180);
  ReferenceStore refs;
  refs.dir = fs::path(o.outDir) / "reference-cache";
  refs.threads = threads;
  refs.log = &log;
  auto settingsFor = [&](const BenchView& view, volume::VolumeRenderMode mode, double step) {
    return referenceSettings(mode, step, view.volume->transfer);
  };
  constexpr auto kDvr = volume::VolumeRenderMode::Dvr;

  if (o.referenceOnly) {
    for (const BenchView& view : views) {
      for (auto mode : kModes) refs.get(view, w, h, settingsFor(view, mode, o.referenceStepMeters));
      if (!plan.bigCells.empty())
        refs.get(view, kBigWidthPx, kBigHeightPx, settingsFor(view, kDvr, o.referenceStepMeters));
      if (!o.quick) {
        refs.get(view, 80, 45, settingsFor(view, kDvr, o.referenceStepMeters));
        refs.get(view, 80, 45, settingsFor(view, kDvr, o.referenceStepMeters / 2.0));
      }
    }
    log << "references: " << refs.rendered << " rendered (" << refs.secondsRendering << " s), " << refs.cached
        << " cached, in " << refs.dir.string() << "\n";
    return VolumeBenchOutcome{};
  }
  engine::VolumeRendererGL& renderer = *benchGL->renderer;

  BenchReport report;
  report.kind = plan.kind;
  report.machine = machineLine(glName);
  report.widthPx = w, report.heightPx = h;
  report.frames = o.frames;
  report.referenceStepMeters = o.referenceStepMeters;
  report.volumes = plan.summaries;
  report.views = views;

  // Load cases (grids: read from a file per view): each in a child process (its own peak memory).
  if (o.load && plan.kind == "grid") {
    std::string self = o.selfExe;
    if (self.empty()) self = fs::read_symlink("/proc/self/exe", ec).string();
    for (const auto& v : plan.volumes) {
      std::vector<LoadCase> c = measureGridLoads(*v, views, self, o.outDir, o.loadRuns, log);
      report.loads.insert(report.loads.end(), c.begin(), c.end());
    }
  }

  // The settings grid at the bench size, against the reference per mode.
  auto target = engine::FramebufferGL::create(w, h);
  if (!target) return target.forwardError();
  globe::Progress progress("bench views", views.size());  // stderr; the log is stdout
  for (const BenchView& view : views) {
    log << "view " << view.name << " (" << w << "x" << h << ")\n";
    std::map<volume::VolumeRenderMode, volume::VolumeImage> ref;
    for (auto mode : kModes) {
      ref[mode] = refs.get(view, w, h, settingsFor(view, mode, o.referenceStepMeters));
      if (Status s = writePngTo(o, view.name + "-reference-" + modeName(mode) + ".png", toRgba8(ref[mode])); !s)
        return s.forwardError();
    }
    if (Status s = measureView(
            o, renderer, view, plan.cells, **target, o.frames, [&](const Cell& c) { return ref[c.mode]; },
            [&](const Cell& c) { return view.name + "-gpu-" + modeName(c.mode) + ".png"; }, report.rows);
        !s)
      return s.forwardError();
    if (plan.kind == "grid")
      if (Status s = measureDetail(
              renderer, view, plan.cells, **target, o.frames, ref[volume::VolumeRenderMode::Dvr],
              [&]() -> std::optional<volume::VolumeImage> {
                if (4 * w > kBigWidthPx || 4 * h > kBigHeightPx) return std::nullopt;
                return averageDown4(refs.get(view, 4 * w, 4 * h,
                                             settingsFor(view, volume::VolumeRenderMode::Dvr, o.referenceStepMeters)));
              },
              report.detailRows);
          !s)
        return s.forwardError();
    progress.advance(1, view.name);
  }

  // 1280x720.
  if (o.big) {
    auto bigTarget = engine::FramebufferGL::create(kBigWidthPx, kBigHeightPx);
    if (!bigTarget) return bigTarget.forwardError();
    // On a software rasteriser (llvmpipe) one 1280x720 frame takes minutes: time-only runs then
    // take the first view only, with one frame.
    const bool software = glName.find("llvmpipe") != std::string::npos || glName.find("softpipe") != std::string::npos;
    for (const BenchView& view : views) {
      if (plan.bigCells.empty()) {
        const engine::Camera camera(view.pose, view.fovYDeg, kBigWidthPx, kBigHeightPx);
        const GpuRun run = timeFramesGL(renderer, camera, *view.glVolume(), optionsFor(Cell{}), Cell{}.beam,
                                        **bigTarget, software ? 1 : o.frames, !software);
        report.big.push_back({view.name + (software ? " (1 frame, software GL)" : ""), run.medianMs});
        if (software) break;
        continue;
      }
      log << "view " << view.name << " (" << kBigWidthPx << "x" << kBigHeightPx << ")\n";
      const volume::VolumeImage ref =
          refs.get(view, kBigWidthPx, kBigHeightPx, settingsFor(view, kDvr, o.referenceStepMeters));
      if (Status s = measureView(
              o, renderer, view, plan.bigCells, **bigTarget, std::min(o.frames, 3), [&](const Cell&) { return ref; },
              [&](const Cell&) { return view.name + "-1280-gpu-dvr.png"; }, report.bigRows);
          !s)
        return s.forwardError();
      if (Status s = writePngTo(o, view.name + "-1280-reference-dvr.png", toRgba8(ref)); !s) return s.forwardError();
      if (plan.kind == "grid")
        if (Status s = measureDetail(
                renderer, view, plan.bigCells, **bigTarget, std::min(o.frames, 3), ref,
                [] { return std::optional<volume::VolumeImage>(); }, report.detailRows);
            !s)
          return s.forwardError();
    }
  }

  // Reference convergence: the reference step against half of it, on a small image.
  for (const BenchView& view : views) {
    if (o.quick) break;
    const volume::VolumeImage a = refs.get(view, 80, 45, settingsFor(view, kDvr, o.referenceStepMeters));
    const volume::VolumeImage b = refs.get(view, 80, 45, settingsFor(view, kDvr, o.referenceStepMeters / 2.0));
    report.convergence.push_back({view.name, volume::compareImages(a, b)});
  }
  report.aggregates = aggregate(report.rows, plan.cells);

  // The peer (its DVR references at the same size come from the cache filled above).
  if (!o.peer) {
    report.peer.note = "peer skipped (--no-peer)";
  } else {
    PeerSettings ps;
    ps.outDir = o.outDir;
    ps.script = findPeerScript(o.peerScript);
    ps.widthPx = w, ps.heightPx = h;
    ps.frames = o.frames;
    ps.maxVoxels = o.quick ? 3.2e7 : plan.peerMaxVoxels;
    ps.threads = threads;
    ps.referenceStepMeters = o.referenceStepMeters;
    Result<PeerSection> peer = runVtkPeer(plan.volumes, views, ps, refs, log);
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
