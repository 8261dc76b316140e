// Benchmark (a program, not a test): the globe at 1280x720 on this machine.
//
//   build/tools/bench/bench_globe_frame [--frames N] [--runs N] [--atmoglobe PATH]   (--help: the options)
//
// Reports, for a set of views (default view first):
//  - frame time: median (and 10th/90th percentile) of N frames after the imagery is
//    resident, each frame ended with glFinish so the GPU (llvmpipe) work is included;
//  - tiles decoded per second: a cold TileImageLoader producing every tile of the default
//    pyramid's levels 0..4 (levels 3-4 are upsampled from level 2), 1 worker thread;
//  - peak resident memory of this process (getrusage);
//  - time from process start to the first image written: `atmoglobe render -o` run as a
//    child process R times (median), the whole command including EGL set-up and decoding.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/ImageryPyramid.h>
#include <atmoglobe/globe/TileImageLoader.h>

#include "BenchCli.h"

#include <epoxy/gl.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

using namespace atmoglobe;
using Clock = std::chrono::steady_clock;

namespace {

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double idx = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(idx);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (v[hi] - v[lo]) * (idx - static_cast<double>(lo));
}

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

struct View {
  const char* name;
  engine::CameraPose pose;
  double fovDeg;
};

}  // namespace

int main(int argc, char** argv) {
  int frames = 60, runs = 7;
  std::string atmoglobe = "build/tools/atmoglobe";
  CLI::App app{
      "Benchmark: the globe at 1280x720 (frame time per view, tiles decoded per second, peak memory, "
      "time to the first image of `atmoglobe render`)",
      "bench_globe_frame"};
  app.add_option("--frames", frames, "Timed frames per view (median, 10th/90th percentile; default 60)")
      ->check(benchcli::numberIn(1));
  app.add_option("--runs", runs, "Runs of `atmoglobe render` timed to the first image (median; default 7)")
      ->check(benchcli::numberIn(1));
  app.add_option("--atmoglobe", atmoglobe, "The atmoglobe program to time (default build/tools/atmoglobe)");
  if (const int rc = benchcli::parse(app, argc, argv); rc >= 0) return rc;
  const std::string pyramid = std::string(ATMOGLOBE_DATA_DIR) + "/earth";
  if (!globe::readPyramidInfo(pyramid)) {
    std::cerr << "bench_globe_frame: " << pyramid << " missing: run ./run.sh first\n";
    return 1;
  }
  auto context = engine::HeadlessContextGL::create();
  if (!context) {
    std::cerr << context.error() << "\n";
    return 1;
  }
  std::cout << "renderer: " << (*context)->describe() << "\n";
  std::cout << "cores: " << sysconf(_SC_NPROCESSORS_ONLN) << "\n\n";

  // 1. Frame time per view.
  const View views[] = {
      {"default (whole globe, 1.4e7 m)", {30.0, 15.0, 1.4e7, 0.0, -90.0, 0.0}, 45.0},
      {"regional, straight down (2e5 m)", {47.0, 8.0, 2e5, 0.0, -90.0, 0.0}, 60.0},
      {"oblique to the horizon (3e3 m)", {45.0, 8.0, 3e3, 20.0, -10.0, 0.0}, 60.0},
      {"ground, 1 m, looking down", {33.65, -101.81, 1.0, 0.0, -90.0, 0.0}, 60.0},
  };
  std::printf("| view | tiles drawn | max level | frame median (ms) | p10 | p90 |\n|---|---|---|---|---|---|\n");
  auto target = engine::FramebufferGL::create(1280, 720);
  if (!target) return 1;
  for (const View& v : views) {
    auto loader = engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, pyramid}}, {});
    auto renderer = engine::SceneRendererGL::create(*loader);
    if (!renderer) {
      std::cerr << renderer.error() << "\n";
      return 1;
    }
    const engine::Camera camera(v.pose, v.fovDeg, 1280, 720);
    engine::SceneFrameStats stats;
    (void)(*renderer)->renderToImage(camera, {}, **target, 64, &stats);  // warm: imagery resident
    std::vector<double> times;
    for (int f = 0; f < frames; ++f) {
      const auto t0 = Clock::now();
      stats = (*renderer)->renderFrame(camera, {}, **target);
      glFinish();
      times.push_back(ms(Clock::now() - t0));
    }
    std::printf("| %s | %d | %d | %.2f | %.2f | %.2f |\n", v.name, stats.globe.tilesDrawn,
                stats.globe.selection.maxLevel, percentile(times, 0.5), percentile(times, 0.1), percentile(times, 0.9));
  }

  // 2. Tile decoding throughput (cold loader, one worker).
  {
    auto loader = engine::openImagery({{engine::ImageryLayerDescription::Type::Pyramid, pyramid}}, {512u << 20, 1});
    std::vector<globe::TileId> tiles;
    for (int z = 0; z <= 4; ++z) {
      for (std::uint32_t y = 0; y < globe::tileRows(z); ++y) {
        for (std::uint32_t x = 0; x < globe::tileColumns(z); ++x) tiles.push_back({z, x, y});
      }
    }
    const auto t0 = Clock::now();
    for (const auto& t : tiles) (void)(*loader)->request(t, 0.0);
    (*loader)->waitIdle();
    const double seconds = ms(Clock::now() - t0) / 1000.0;
    std::printf("\ntiles decoded: %zu (levels 0..4) in %.2f s: %.0f tiles/s (1 worker; levels 3-4 upsampled)\n",
                tiles.size(), seconds, static_cast<double>(tiles.size()) / seconds);
  }

  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak resident memory of this benchmark process: %.1f MiB\n",
              static_cast<double>(usage.ru_maxrss) / 1024.0);

  // 3. Process start to first image written (the real command, R runs).
  std::vector<double> startTimes;
  double childPeakMiB = 0.0;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = Clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
      const int devnull = open("/dev/null", O_WRONLY);
      dup2(devnull, 1);
      execl(atmoglobe.c_str(), atmoglobe.c_str(), "render", "-o", "/tmp/atmoglobe-bench-first.png", nullptr);
      _exit(127);
    }
    int status = 0;
    rusage child{};
    wait4(pid, &status, 0, &child);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::cerr << "bench_globe_frame: " << atmoglobe << " render failed\n";
      return 1;
    }
    startTimes.push_back(ms(Clock::now() - t0));
    childPeakMiB = std::max(childPeakMiB, static_cast<double>(child.ru_maxrss) / 1024.0);
  }
  std::printf(
      "start to first image (`atmoglobe render`, default scene, %d runs): median %.0f ms (min %.0f, max %.0f)\n", runs,
      percentile(startTimes, 0.5), percentile(startTimes, 0.0), percentile(startTimes, 1.0));
  std::printf("peak resident memory of `atmoglobe render`: %.1f MiB\n", childPeakMiB);
  return 0;
}
