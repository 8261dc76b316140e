// atmoglobe render: draws a scene headless (EGL, no window, no X server) into a PNG.
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/engine/AnimationWriter.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/engine/ViewCulling.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/Progress.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/StepCache.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

namespace atmoglobe::tools {

namespace {
struct RenderOptions {
  SceneOptions scene;
  std::string output = "out/render.png";
  bool stats = false;
  bool reference = false;
  int threads = 2;
  bool timeSeries = false;
  int timeSubsteps = 1;
  bool noLegend = false;
  bool strict = false;
  bool loadAll = false;                 ///< --load-all: no view culling of radars at load
  std::vector<std::string> animations;  ///< --animation FILE.gif / FILE.mp4
  double framesPerSecond = 4.0;
  std::string shard;  ///< --shard K/N (docs/scale-out.md); empty: $SLURM_ARRAY_TASK_ID/COUNT if set
};

struct Shard {
  std::size_t index = 0, count = 1;
  std::string from;  ///< where it was given, for the message
};

// A whole non-negative decimal number, or nothing.
std::optional<std::size_t> wholeNumber(const std::string& text) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  return static_cast<std::size_t>(std::stoul(text));
}

// The shard of a series this run renders: --shard K/N, else a Slurm array task's
// (SLURM_ARRAY_TASK_ID minus SLURM_ARRAY_TASK_MIN, of SLURM_ARRAY_TASK_COUNT), else none.
Result<std::optional<Shard>> shardToRender(const std::string& option) {
  if (!option.empty()) {
    const std::size_t slash = option.find('/');
    const auto k = wholeNumber(option.substr(0, slash));
    const auto n = slash == std::string::npos ? std::nullopt : wholeNumber(option.substr(slash + 1));
    if (!k || !n || *n == 0 || *k >= *n)
      return makeError("--shard " + option + ": expected K/N, shard K (0 to N-1) of N shards, e.g. 0/4");
    return std::optional<Shard>(Shard{*k, *n, "--shard"});
  }
  const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
  const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
  if (!id || !count) return std::optional<Shard>();
  const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
  const auto k = wholeNumber(id), n = wholeNumber(count),
             first = min ? wholeNumber(min) : std::optional<std::size_t>(0);
  if (!k) return makeError(std::string("SLURM_ARRAY_TASK_ID=") + id + ": not a task number");
  if (!n || *n == 0) return makeError(std::string("SLURM_ARRAY_TASK_COUNT=") + count + ": not a task count");
  if (!first || *first > *k)
    return makeError(std::string("SLURM_ARRAY_TASK_MIN=") + (min ? min : "") + ": not a task number at or below " +
                     "SLURM_ARRAY_TASK_ID=" + id);
  // Arrays with a step (--array=0-30:10) or lists have ids that are not consecutive: the shard
  // would skip frames, so such arrays are refused rather than rendered incompletely.
  if (*k - *first >= *n)
    return makeError(std::string("SLURM_ARRAY_TASK_ID=") + id + " is not within SLURM_ARRAY_TASK_MIN=" +
                     std::to_string(*first) + " and the " + count + " tasks of the array: give the array as a range " +
                     "(sbatch --array=0-" + std::to_string(*n - 1) + ") or --shard K/N");
  return std::optional<Shard>(Shard{*k - *first, *n, "SLURM_ARRAY_TASK_ID/COUNT"});
}

// NAME.png -> NAME_007.png (frame 7 of a series).
std::string seriesPath(const std::string& output, std::size_t frame) {
  const std::filesystem::path p(output);
  char number[24];  // "_" and up to 20 digits of a size_t
  std::snprintf(number, sizeof number, "_%03zu", frame);
  return (p.parent_path() / (p.stem().string() + number + p.extension().string())).string();
}

// One line of what the series held (docs/memory.md; the memory-budget test reads it).
void printMemoryLine(const volume::StepCache::Stats& c, std::uint64_t rssBeforeBytes, std::uint64_t rssFirstBytes) {
  const auto mib = [](std::uint64_t b) { return std::to_string(b / 1048576); };
  std::cerr << "memory: budget " << mib(c.budgetBytes) << " MiB, steps held peak " << mib(c.peakHeldBytes) << " MiB ("
            << c.misses << " misses, " << c.hits << " hits, " << c.drops << " dropped); RSS before the series "
            << mib(rssBeforeBytes) << " MiB, after its first frame " << mib(rssFirstBytes) << " MiB, peak RSS "
            << mib(volume::peakResidentBytes()) << " MiB\n";
}

int runRender(const RenderOptions& o) {
  if (!o.shard.empty() && !o.timeSeries) return fail("render", "--shard needs --time-series");
  std::optional<Shard> shard;
  if (o.timeSeries) {
    auto s = shardToRender(o.shard);
    if (!s) return fail("render", s.error());
    shard = *s;
    if (shard && !o.animations.empty())
      return fail("render",
                  "--animation needs the whole series: make it after every shard has rendered (e.g. "
                  "ffmpeg over NAME_%03d.png), not in one shard (" +
                      shard->from + ")");
  }
  auto scene = resolveScene(o.scene);
  if (!scene) return fail("render", scene.error());
  if (!o.loadAll) {
    // Load only what the camera shows: radars whose volume is outside the view are not read.
    const engine::Camera view(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
    const engine::CullOutcome cull = engine::cullRadarsOutsideView(*scene, view);
    if (!cull.culled.empty())
      std::cerr << "atmoglobe render: " << cull.culled.size() << " of " << cull.culled.size() + cull.kept
                << " radars outside the view, not loaded (--load-all loads them)\n";
  }
  auto context = engine::HeadlessContextGL::create();
  if (!context) return fail("render", context.error());
  auto loader = engine::openImagery(scene->imagery, {});
  if (!loader) return fail("render", loader.error());
  auto renderer = engine::SceneRendererGL::create(*loader);
  if (!renderer) return fail("render", renderer.error());
  std::vector<engine::Marker> markers = scene->markers;
  // Inputs that fail are reported and left out (exit 3 once the picture is written), unless --strict.
  std::vector<std::string> inputErrors;
  if (auto s = populateScene(**renderer, *scene, &markers, o.strict ? nullptr : &inputErrors); !s)
    return fail("render", s.error());
  for (const std::string& e : inputErrors) std::cerr << "atmoglobe render: error: " << e << "\n";
  auto done = [&]() {
    if (inputErrors.empty()) return 0;
    std::cerr << "atmoglobe render: rendered with " << inputErrors.size() << " input error"
              << (inputErrors.size() > 1 ? "s" : "") << " (exit status " << kExitRenderedWithErrors
              << "; --strict stops at the first)\n";
    return kExitRenderedWithErrors;
  };
  auto target = engine::FramebufferGL::create(scene->widthPx, scene->heightPx);
  if (!target) return fail("render", target.error());
  const engine::Camera camera(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
  engine::SceneFrameStats stats;
  // --reference: the frame as always (globe, models, markers, labels), with the volumes drawn
  // by the CPU reference renderer (double precision, exact inverse geolocation, same settings)
  // in the marcher's place.
  if (o.reference) (*renderer)->setReferenceVolumes(std::max(1, o.threads));
  const std::filesystem::path parent = std::filesystem::path(o.output).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (ec) return fail("render", parent.string() + ": cannot create directory: " + ec.message());
  if (!o.animations.empty() && !o.timeSeries) return fail("render", "--animation needs --time-series");
  if (o.timeSeries) {
    // One PNG per time step (and substep): NAME_000.png, NAME_001.png, ...
    if (o.timeSubsteps < 1 || o.timeSubsteps > 100) return fail("render", "--time-substeps must be 1..100");
    auto axis = engine::sceneTimeAxis(**renderer);
    if (!axis) return fail("render", axis.error());
    for (const std::string& note : axis->notes) std::cerr << "atmoglobe render: " << note << "\n";
    std::cerr << "atmoglobe render: " << axis->times.size() << " time steps from " << axis->leadName
              << "; colours and opacity stay those of the step first loaded\n";
    // --animation: a GIF takes each frame as it is made; an MP4 is encoded from the PNGs after.
    std::vector<std::unique_ptr<engine::GifAnimationWriter>> gifs;
    std::vector<std::string> gifPaths, mp4s;
    for (const std::string& a : o.animations) {
      const std::string ext = std::filesystem::path(a).extension().string();
      if (ext == ".gif" || ext == ".GIF") {
        auto gif = engine::GifAnimationWriter::create(a, scene->widthPx, scene->heightPx,
                                                      static_cast<int>(std::lround(1000.0 / o.framesPerSecond)));
        if (!gif) return fail("render", gif.error());
        gifs.push_back(std::move(*gif));
        gifPaths.push_back(a);
      } else if (ext == ".mp4" || ext == ".MP4") {
        mp4s.push_back(a);
      } else {
        return fail("render", "--animation " + a + ": the name must end in .gif or .mp4");
      }
    }
    // The frames this run renders: all, or its shard's (numbered as in the whole series).
    const std::size_t frames = engine::seriesFrameCount(axis->times.size(), o.timeSubsteps);
    engine::FrameRange range{0, frames};
    if (shard) {
      auto r = engine::seriesShard(frames, shard->index, shard->count);
      if (!r) return fail("render", r.error());
      range = *r;
      std::cerr << "atmoglobe render: shard " << shard->index << "/" << shard->count << " (" << shard->from
                << "): frames " << range.begin << " to " << range.end << " (exclusive) of " << frames << "\n";
      if (range.size() == 0) {
        std::cerr << "atmoglobe render: this shard has no frames (more shards than the " << frames
                  << " frames of the series)\n";
        return done();
      }
    }
    std::size_t frame = 0, rendered = 0;
    const std::uint64_t rssBefore = volume::currentResidentBytes();
    std::uint64_t rssFirst = 0;  // peak RSS after the first frame (shaders compiled, one step shown)
    globe::Progress progress("frames", range.size());
    for (std::size_t step = 0; step < axis->times.size(); ++step) {
      const int subs = step + 1 < axis->times.size() ? o.timeSubsteps : 1;
      for (int sub = 0; sub < subs; ++sub, ++frame) {
        if (!range.contains(frame)) continue;
        auto when = engine::showSceneTime(**renderer, *axis, step, static_cast<double>(sub) / o.timeSubsteps);
        if (!when) return fail("render", when.error());
        auto image = (*renderer)->renderToImage(camera, markers, **target, 64, &stats);
        if (!image) return fail("render", image.error());
        if (!o.noLegend)
          if (auto st = engine::drawFrameLegend(*image, (*renderer)->legendFor(camera)); !st)
            return fail("render", st.error());
        const std::string path = seriesPath(o.output, frame);
        if (auto s = globe::writePng(path, *image); !s) return fail("render", s.error());
        for (auto& gif : gifs)
          if (auto s = gif->addFrame(*image); !s) return fail("render", s.error());
        progress.print(path + " " + *when, stdout);  // the result line, not mixed into a bar
        progress.advance(1, *when);
        if (rendered++ == 0) rssFirst = volume::peakResidentBytes();
      }
    }
    progress.finish();
    printMemoryLine((*renderer)->stepCache().stats(), rssBefore, rssFirst);
    for (std::size_t i = 0; i < gifs.size(); ++i) {
      if (auto s = gifs[i]->finish(); !s) return fail("render", s.error());
      progress.print(gifPaths[i] + " (" + std::to_string(frame) + " frames)", stdout);
    }
    for (const std::string& mp4 : mp4s) {
      // The PNGs just written, NAME_%03d.png (frames beyond 999 keep counting: %03d widens).
      const std::filesystem::path p(o.output);
      const std::string pattern = (p.parent_path() / (p.stem().string() + "_%03d" + p.extension().string())).string();
      if (auto s = engine::encodeMp4(pattern, o.framesPerSecond, mp4); !s) {
        if (engine::findFfmpeg().empty()) {
          std::cerr << "atmoglobe render: skipped " << mp4 << ": ffmpeg not found on PATH (Debian package ffmpeg)\n";
          continue;
        }
        return fail("render", s.error());
      }
      progress.print(mp4 + " (" + std::to_string(frame) + " frames)", stdout);
    }
    return done();
  }
  auto image = (*renderer)->renderToImage(camera, markers, **target, 64, &stats);
  if (!image) return fail("render", image.error());
  if (o.reference) std::cerr << "reference volumes: " << stats.referenceSeconds << " s\n";
  if (!o.noLegend)
    if (auto st = engine::drawFrameLegend(*image, (*renderer)->legendFor(camera)); !st)
      return fail("render", st.error());
  if (auto s = globe::writePng(o.output, *image); !s) return fail("render", s.error());
  if (o.stats) {
    std::cerr << "renderer: " << (*context)->describe() << "\n"
              << "tiles drawn: " << stats.globe.tilesDrawn << " (max level " << stats.globe.selection.maxLevel
              << ", visited " << stats.globe.selection.visited << ", culled frustum "
              << stats.globe.selection.culledFrustum << ", horizon " << stats.globe.selection.culledHorizon << ")\n"
              << "tiles decoded: " << (*loader)->stats().tilesDecoded << "\n";
    for (std::size_t i = 0; i < (*renderer)->volumeLayerCount(); ++i) {
      const auto* radar = (*renderer)->layerAs<engine::RadarSourceGL>(i);
      if (!radar) continue;  // the Cartesian comparison is a radar's
      const auto& polar = radar->radarVolume().polar();
      std::cerr << "radar " << polar.sourcePath << " (" << polar.fieldName << "): " << polar.sweeps.size()
                << " sweeps, GPU " << static_cast<double>(radar->volume().gpuBytes()) / 1048576.0
                << " MiB; a Cartesian grid at its near-range resolution would need "
                << volume::cartesianEquivalentBytes(polar, 1.0) / 1048576.0 << " MiB at 1 byte/voxel\n";
    }
  }
  std::cout << o.output << "\n";
  return done();
}
}  // namespace

Command addRenderCommand(CLI::App& root) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* c = root.add_subcommand("render", "Render a scene headless (EGL, no window) to a PNG file");
  addSceneOptions(*c, options->scene);
  c->add_option("-o,--output", options->output, "Output PNG file")->capture_default_str();
  c->add_flag("--stats", options->stats, "Print renderer, tile, decoding and volume memory statistics to stderr");
  c->add_flag("--reference", options->reference,
              "Draw the volumes with the CPU reference renderer (double precision, exact geolocation; slow: "
              "~1-2 us per sample) in the GPU marcher's place; globe, markers, labels and models as always");
  c->add_option("--threads", options->threads, "Threads for --reference")->capture_default_str();
  c->add_flag("--strict", options->strict,
              "Stop at the first input that cannot be loaded (exit 1); by default each is reported, left out, and "
              "the picture written with exit status 3");
  c->add_flag("--no-legend", options->noLegend,
              "No title, colour keys, scale bar or SYNTHETIC mark drawn over the picture");
  c->add_flag("--time-series", options->timeSeries,
              "One PNG per time step of the scene's grids: -o NAME.png writes NAME_000.png, NAME_001.png, ... "
              "(each path and its valid time printed)");
  c->add_option("--time-substeps", options->timeSubsteps,
                "With --time-series: frames per step, the grids interpolated linearly in time between steps")
      ->capture_default_str();
  c->add_flag("--load-all", options->loadAll,
              "Load every radar of the scene, also those whose volume is outside the camera's view");
  c->add_option("--animation", options->animations,
                "With --time-series: also an animated FILE.gif (giflib, 256 colours per frame) or FILE.mp4 "
                "(H.264 through ffmpeg when it is on PATH; skipped with a message otherwise); repeatable");
  c->add_option("--shard", options->shard,
                "With --time-series: render shard K (0 to N-1) of N, a contiguous run of the series' frames named "
                "as in the whole series (a Slurm array task: read from SLURM_ARRAY_TASK_ID and "
                "SLURM_ARRAY_TASK_COUNT when not given; docs/scale-out.md)");
  c->add_option("--fps", options->framesPerSecond, "With --animation: frames per second")
      ->check(CLI::Range(0.1, 60.0))
      ->capture_default_str();
  c->footer("Example: atmoglobe render --camera 46,8,2e6,0,-90,0 --size 1280x720 -o out/alps.png");
  return {c, [options] { return runRender(*options); }};
}

}  // namespace atmoglobe::tools
