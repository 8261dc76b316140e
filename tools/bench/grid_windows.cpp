// Benchmark (a program, not a test): a grid too large for the GPU, drawn near and far.
//
//   build/tools/bench/bench_grid_windows [--grid FILE] [--limits MB,...] [--sizes WxH,...]
//       [--runs N] [--frames N] [--out DIR]      (--help: the options, their defaults and bounds)
//
// A grid whose texture is over the GPU's limit ($ATMOGLOBE_MAX_TEXTURE_BYTES here) is uploaded at
// 1/2, 1/4 ... of its resolution; a view draws the window of its columns in view at the finest
// resolution at which that window fits, and where that is still coarser than the grid, the columns
// nearest the eye at full resolution in the same frame (docs/grids.md, "Near and far in one
// frame"). Per view, limit and size, four ways of drawing the frame:
//  - whole: no limit (the grid itself, what the others are compared with);
//  - uploaded: the grid as uploaded under the limit (--grid-lod off);
//  - one window: the window in view, one resolution throughout (--grid-near-window off);
//  - near + far: the default, the near window at full resolution with the rest coarser.
// Per way: the median frame time (the whole frame, globe and grid, each ended by glFinish; the
// median of --frames frames per run, then of --runs runs, the four ways in turn within a run) and
// the frame's mean absolute difference from the whole grid's (RGB, 8-bit steps) with the share
// of pixels off by 6 or more. The grid defaults to the SYNTHETIC global 0.25-degree grid of
// `atmoglobe bench --grids` (written to --out/grids when missing).
#include <atmoglobe/bench/GridViews.h>
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/GridSourceGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>

#include "BenchCli.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

using namespace atmoglobe;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

struct View {
  const char* name;
  engine::CameraPose pose;
};

// Oblique views of the SYNTHETIC global grid's cyclone (18 N 62 W) and of the open Atlantic, and
// one straight down from 4,000 km (docs/grids.md's table of windows).
const std::vector<View>& views() {
  static const std::vector<View> v{
      {"cyclone-oblique-1500km", engine::CameraPose{5.0, -62.0, 1.5e6, 0.0, -40.0, 0.0}},
      {"atlantic-oblique-3000km", engine::CameraPose{0.0, -40.0, 3.0e6, 0.0, -35.0, 0.0}},
      {"cyclone-down-4000km", engine::CameraPose{18.0, -62.0, 4.0e6, 0.0, -90.0, 0.0}},
  };
  return v;
}

enum class Way { Whole, Uploaded, OneWindow, NearFar };
const char* wayName(Way w) {
  switch (w) {
    case Way::Whole: return "whole (no limit)";
    case Way::Uploaded: return "grid as uploaded";
    case Way::OneWindow: return "one window";
    case Way::NearFar: return "near + far";
  }
  return "";
}

struct Drawn {
  std::unique_ptr<engine::SceneRendererGL> renderer;
  engine::GridSourceGL* grid = nullptr;
};

// A scene of the grid's whole shell (the test's colours and opacity: dBZ) under `limitBytes`
// (0: none) drawn `way`.
Result<Drawn> sceneFor(const std::shared_ptr<globe::TileImageLoader>& loader, const std::string& path,
                       std::uint64_t limitBytes, Way way) {
  auto renderer = engine::SceneRendererGL::create(loader);
  if (!renderer) return renderer.forwardError();
  engine::VolumeLayerDescription d;
  d.kind = engine::VolumeKind::Grid;
  d.path = path;
  d.levelOfDetail = way != Way::Uploaded;
  d.nearWindow = way == Way::NearFar;
  if (limitBytes > 0) setenv("ATMOGLOBE_MAX_TEXTURE_BYTES", std::to_string(limitBytes).c_str(), 1);
  else unsetenv("ATMOGLOBE_MAX_TEXTURE_BYTES");
  auto layer = (*renderer)->addVolume(d);
  if (!layer) return layer.forwardError();
  Drawn out;
  out.grid = dynamic_cast<engine::GridSourceGL*>(*layer);
  out.renderer = std::move(*renderer);
  if (!out.grid) return makeError(path + ": not a grid layer");
  return out;
}

double meanDifference(const globe::ImageRGBA8& a, const globe::ImageRGBA8& b, double* shareOver6) {
  double sum = 0.0;
  long over = 0;
  const std::size_t n = static_cast<std::size_t>(a.width) * static_cast<std::size_t>(a.height);
  for (std::size_t i = 0; i < n; ++i) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int d = std::abs(int(a.pixels[4 * i + c]) - int(b.pixels[4 * i + c]));
      sum += d;
      worst = std::max(worst, d);
    }
    over += worst >= 6 ? 1 : 0;
  }
  *shareOver6 = 100.0 * static_cast<double>(over) / static_cast<double>(n);
  return sum / (3.0 * static_cast<double>(n));
}

std::vector<std::string> splitCommas(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string grid, out = "out/bench", limitsText = "100,30", sizesText = "640x360,1280x720";
  int runs = 3, frames = 3;
  CLI::App app{
      "Benchmark: a grid too large for the GPU drawn near and far: frame time and difference from the whole "
      "grid (docs/grids.md)",
      "bench_grid_windows"};
  app.add_option("--grid", grid, "The grid file (default: the SYNTHETIC global 0.25-degree grid in --out/grids)");
  app.add_option("--limits", limitsText, "GPU texture limits in MB, comma-separated (default 100,30)");
  app.add_option("--sizes", sizesText, "Image sizes WxH, comma-separated (default 640x360,1280x720)");
  app.add_option("--runs", runs, "Runs (median of the runs' medians; default 3)")->check(benchcli::numberIn(1));
  app.add_option("--frames", frames, "Timed frames per run (median; default 3)")->check(benchcli::numberIn(1));
  app.add_option("--out", out, "Output directory (the built-in grid; default out/bench)");
  if (const int rc = benchcli::parse(app, argc, argv); rc >= 0) return rc;
  std::vector<double> limitsMb;
  for (const std::string& t : splitCommas(limitsText)) {
    char* end = nullptr;
    const double mb = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0' || !(mb >= 1.0)) {
      std::cerr << "--limits " << limitsText << ": expected numbers >= 1 (MB), comma-separated\n";
      return 2;
    }
    limitsMb.push_back(mb);
  }
  std::vector<std::pair<int, int>> sizes;
  for (const std::string& t : splitCommas(sizesText)) {
    int w = 0, h = 0;
    if (!benchcli::parseSize(t, w, h)) {
      std::cerr << "--sizes " << sizesText << ": expected WxH, each >= 16, comma-separated\n";
      return 2;
    }
    sizes.emplace_back(w, h);
  }
  if (grid.empty()) {
    for (const bench::GridBenchFile& f : bench::builtinGridFiles(fs::path(out) / "grids"))
      if (f.key == "global") {
        if (auto st = bench::ensureGridFile(f, std::cerr); !st) {
          std::cerr << st.error() << "\n";
          return 1;
        }
        grid = f.path;
      }
  }
  auto context = engine::HeadlessContextGL::create();
  if (!context) {
    std::cerr << context.error() << "\n";
    return 1;
  }
  auto loader = engine::openImagery({}, {});
  if (!loader) {
    std::cerr << loader.error() << "\n";
    return 1;
  }
  std::printf(
      "renderer: %s\ngrid: %s\n%d runs x %d frames (median of run medians), the whole frame (globe and grid)\n\n",
      reinterpret_cast<const char*>(glGetString(GL_RENDERER)), grid.c_str(), runs, frames);
  std::printf(
      "| view | limit | size | way | drawn | ms | mean abs diff | px off >= 6 |\n|---|---|---|---|---|---|---|---|\n");
  for (const auto& [w, h] : sizes) {
    auto target = engine::FramebufferGL::create(w, h);
    if (!target) {
      std::cerr << target.error() << "\n";
      return 1;
    }
    for (const double mb : limitsMb) {
      const auto limit = static_cast<std::uint64_t>(mb * 1e6);
      // The scenes stay open through the runs (each keeps its windows, as the viewer does).
      const std::vector<Way> ways{Way::Whole, Way::Uploaded, Way::OneWindow, Way::NearFar};
      std::vector<Drawn> scenes;
      for (const Way way : ways) {
        auto s = sceneFor(*loader, grid, way == Way::Whole ? 0 : limit, way);
        if (!s) {
          std::cerr << s.error() << "\n";
          return 1;
        }
        scenes.push_back(std::move(*s));
      }
      for (const View& view : views()) {
        const engine::Camera camera(view.pose, 45.0, w, h);
        std::vector<std::vector<double>> runMedians(ways.size());
        std::vector<globe::ImageRGBA8> images(ways.size());
        std::vector<std::string> drawn(ways.size());
        for (int run = 0; run < runs; ++run)
          for (std::size_t k = 0; k < ways.size(); ++k) {
            engine::SceneRendererGL& r = *scenes[k].renderer;
            if (ways[k] == Way::Whole) unsetenv("ATMOGLOBE_MAX_TEXTURE_BYTES");
            else setenv("ATMOGLOBE_MAX_TEXTURE_BYTES", std::to_string(limit).c_str(), 1);
            if (run == 0) {  // untimed: brings the imagery in, makes the windows; the picture
              auto image = r.renderToImage(camera, {}, **target);
              if (!image) {
                std::cerr << image.error() << "\n";
                return 1;
              }
              images[k] = std::move(*image);
              drawn[k] = scenes[k].grid->legendPart().subtitle;
              const std::size_t at = drawn[k].find("  ");
              drawn[k] = at == std::string::npos ? "" : drawn[k].substr(drawn[k].find_first_not_of(' ', at));
            }
            std::vector<double> ms;
            for (int f = 0; f < frames; ++f) {
              (*target)->bind();
              const auto t0 = Clock::now();
              r.renderFrame(camera, {}, **target);
              glFinish();
              ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
            }
            runMedians[k].push_back(bench::median(ms));
          }
        for (std::size_t k = 0; k < ways.size(); ++k) {
          double over = 0.0;
          const double diff = meanDifference(images[k], images[0], &over);
          std::printf("| %s | %g MB | %dx%d | %s | %s | %.1f | %.3f | %.2f %% |\n", view.name, mb, w, h,
                      wayName(ways[k]), ways[k] == Way::Whole ? "the grid" : drawn[k].c_str(),
                      bench::median(runMedians[k]), diff, over);
          std::fflush(stdout);
        }
      }
    }
  }
  unsetenv("ATMOGLOBE_MAX_TEXTURE_BYTES");
  return 0;
}
