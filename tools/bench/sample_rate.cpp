// Benchmark (a program, not a test): samples per second of the radar march against what the device
// can fetch.
//
//   build/tools/bench/bench_sample_rate [--radar FILE] [--sizes 320x180,1280x720] [--runs N] [--frames N]
//       (--help: the options, their defaults and bounds)
//
// One radar (default: KLBB from ../shared/data, else the built default SYNTHETIC KTLX) seen as the
// volume bench's oblique view sees KLBB (100 km up, 200 km south of the antenna, 27 deg down, 50
// deg field of view), drawn with the default settings (DVR, 250 m, linear, the 4/3 beam, empty-
// space skipping). Per size:
//  - the march's median frame time (glFinish per frame) and the samples it takes
//    (VolumeRendererGL::sampleCounts: one per position sampled, after skipping and early
//    termination), so samples per second;
//  - the device's rate of bilinear fetches from a texture of the radar's values' shape (RG16F,
//    gates x rays x sweeps; shaders/fetch_rate.frag), from the difference between 128 and 64
//    fetches a pixel (the pass's fixed cost cancels);
//  - the bound that rate puts on samples per second: a sample reads the two bracketing sweeps'
//    values (two such fetches; its other fetches, small tables, are left out, so the bound is
//    generous), and the fraction of it the march reaches.
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarLoad.h>

#include "BenchCli.h"

#include <epoxy/gl.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <random>
#include <string>
#include <vector>

using namespace atmoglobe;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Median ms of `frames` draws of the fetch pass with `fetches` lookups a pixel.
double timeFetchPass(const engine::ShaderProgramGL& program, const engine::FramebufferGL& target, GLuint vao,
                     GLuint texture, int fetches, int frames) {
  target.bind();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  program.use();
  glBindTextureUnit(0, texture);
  glUniform1i(program.uniform("u_fetches"), fetches);
  glBindVertexArray(vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);  // untimed: compiles the shader's state
  glFinish();
  std::vector<double> ms;
  for (int f = 0; f < frames; ++f) {
    const auto t0 = Clock::now();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glFinish();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  glBindVertexArray(0);
  return bench::median(ms);
}

}  // namespace

int main(int argc, char** argv) {
  std::string radarPath;
  std::vector<std::pair<int, int>> sizes{{320, 180}, {1280, 720}};
  int runs = 3, frames = 5;
  CLI::App app{"Samples per second of the radar march against what the device can fetch (docs/bench-volume.md)",
               "bench_sample_rate"};
  app.add_option("--radar", radarPath,
                 "Radar file (default: ../shared/data/radar_nexrad/KLBB20160601_150025_V06, else the default "
                 "SYNTHETIC KTLX)");
  benchcli::addSizesOption(app, sizes, "Image sizes, comma-separated (default 320x180,1280x720)");
  app.add_option("--runs", runs, "Runs per size (median of the runs' medians; default 3)")
      ->check(benchcli::numberIn(1));
  app.add_option("--frames", frames, "Timed frames per run (median; default 5)")->check(benchcli::numberIn(1));
  if (const int rc = benchcli::parse(app, argc, argv); rc >= 0) return rc;

  if (radarPath.empty()) {
    const fs::path klbb = fs::path(ATMOGLOBE_SHARED_DATA_DIR) / "radar_nexrad" / "KLBB20160601_150025_V06";
    radarPath = fs::exists(klbb) ? klbb.string() : (fs::path(ATMOGLOBE_DATA_DIR) / "synthetic_ktlx.nc").string();
  }
  auto context = engine::HeadlessContextGL::create();
  if (!context) {
    std::cerr << "bench_sample_rate: " << context.error() << "\n";
    return 1;
  }
  volume::RadarLoadOptions load;
  load.buildRenderLayout = true;
  auto loaded = volume::loadRadar(radarPath, load);
  if (!loaded) {
    std::cerr << "bench_sample_rate: " << radarPath << ": " << loaded.error() << "\n";
    return 1;
  }
  const volume::PolarVolume polar = std::move(*loaded->layout);
  auto gl = engine::RadarVolumeGL::create(polar);
  auto renderer = engine::VolumeRendererGL::create();
  auto fetch = engine::ShaderProgramGL::create("fullscreen.vert", "fetch_rate.frag");
  if (!gl || !renderer || !fetch) {
    std::cerr << "bench_sample_rate: " << (!gl ? gl.error() : !renderer ? renderer.error() : fetch.error()) << "\n";
    return 1;
  }

  // A texture of the values' shape, filled with noise (the fetch cost does not depend on values).
  const int gates = polar.maxGates + 1, rays = polar.maxRays + 1, layers = static_cast<int>(polar.sweeps.size());
  GLuint values = 0, vao = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &values);
  glTextureStorage3D(values, 1, GL_RG16F, gates, rays, layers);
  {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.0f, 60.0f);
    std::vector<float> texels(static_cast<std::size_t>(gates) * static_cast<std::size_t>(rays) * 2);
    for (int l = 0; l < layers; ++l) {
      for (float& t : texels) t = u(rng);
      glTextureSubImage3D(values, 0, 0, 0, l, gates, rays, 1, GL_RG, GL_FLOAT, texels.data());
    }
  }
  glTextureParameteri(values, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(values, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glCreateVertexArrays(1, &vao);
  glProgramUniform1i(fetch->id(), fetch->uniform("u_values"), 0);
  glProgramUniform1f(fetch->id(), fetch->uniform("u_layers"), static_cast<float>(layers));

  const char* rendererName = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  std::printf("# Samples per second against the fetch rate (bench_sample_rate)\n\n");
  std::printf("renderer: %s\ncores: %ld\nradar: %s (%d sweeps, up to %d rays x %d gates)\n", rendererName,
              sysconf(_SC_NPROCESSORS_ONLN), radarPath.c_str(), layers, polar.maxRays, polar.maxGates);
  std::printf(
      "view: 100 km up, 200 km south of the antenna, heading 0, pitch -27.05 deg, fov 50 deg; default "
      "settings (DVR, 250 m, linear, 4/3 beam, skipping); %d runs x %d frames (median of run medians)\n\n",
      runs, frames);
  std::printf(
      "| size | march (ms) | samples (M) | samples/s (M) | bilinear fetches/s (M) | bound: 2 fetches a sample "
      "(M samples/s) | reached |\n|---|---|---|---|---|---|---|\n");
  const double siteLat = polar.site.latDeg, siteLon = polar.site.lonDeg;
  for (const auto& [w, h] : sizes) {
    const engine::Camera camera(engine::CameraPose{siteLat - 1.8033, siteLon, 100e3, 0.0, -27.05, 0.0}, 50.0, w, h);
    auto target = engine::FramebufferGL::create(w, h);
    if (!target) {
      std::cerr << "bench_sample_rate: " << target.error() << "\n";
      return 1;
    }
    engine::VolumeRenderOptions options;
    const std::vector<engine::VolumeLayerGL> layerList{engine::VolumeLayerGL{gl->get(), options}};
    const std::vector<float> counts = (*renderer)->sampleCounts(camera, layerList);
    double samples = 0.0;
    for (float c : counts) samples += c;
    std::vector<double> marchRuns, fetchRuns;
    for (int r = 0; r < runs; ++r) {
      marchRuns.push_back(bench::timeLayersGL(**renderer, camera, layerList, **target, frames));
      const double ms64 = timeFetchPass(*fetch, **target, vao, values, 64, frames);
      const double ms128 = timeFetchPass(*fetch, **target, vao, values, 128, frames);
      std::fprintf(stderr, "fetch pass: 64 a pixel %.2f ms, 128 %.2f ms\n", ms64, ms128);
      fetchRuns.push_back(std::max(ms128 - ms64, 1e-3));
    }
    const double marchMs = bench::median(marchRuns), fetch64Ms = bench::median(fetchRuns);
    const double samplesPerS = samples / (marchMs * 1e-3);
    const double fetchesPerS = double(w) * double(h) * 64.0 / (fetch64Ms * 1e-3);
    const double bound = fetchesPerS / 2.0;
    std::printf("| %dx%d | %.2f | %.2f | %.1f | %.1f | %.1f | %.0f %% |\n", w, h, marchMs, samples * 1e-6,
                samplesPerS * 1e-6, fetchesPerS * 1e-6, bound * 1e-6, 100.0 * samplesPerS / bound);
    std::fflush(stdout);
  }
  glDeleteVertexArrays(1, &vao);
  glDeleteTextures(1, &values);
  return 0;
}
