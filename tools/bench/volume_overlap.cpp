// Benchmark (a program, not a test): the cost of several volumes in one march.
//
//   build/tools/bench/bench_volume_overlap [--runs N] [--frames N] [--size WxH] [--step M] [--out DIR]
//       (--help: the options, their defaults and bounds)
//
// The rule under test (docs/volume-rendering.md, "Several volumes in one march"): a pixel pays
// only for the volumes its ray crosses, and only along each volume's own interval. N = 1, 2, 4, 8
// synthetic radars (volume::writeSyntheticCfRadial, 80 km range, VCP 212) in two layouts:
//  - stacked: the radars on a 40 km circle around one point, each with its storm at that point,
//    so every ray through the storm crosses all N volumes;
//  - apart: the radars 250 km apart in a row (no two clip spheres overlap), seen from above, so a
//    ray crosses at most one.
// Per case: the work the rule predicts, W = sum over pixels and volumes of the samples inside the
// volume's ray interval before the ellipsoid (computed on the CPU with each volume's
// VolumeSampler::rayInterval: the same intervals the shader computes), and the median GPU frame
// time (glFinish per frame; median of --frames frames per run, then the median of --runs runs),
// with and without empty-space skipping. If the rule holds, time per million interval samples
// stays flat as N grows (without skipping, where every interval sample is taken).
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include "BenchCli.h"

#include <epoxy/gl.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

using namespace atmoglobe;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

struct Radar {
  std::unique_ptr<volume::PolarVolume> polar;
  std::unique_ptr<engine::RadarVolumeGL> gl;
};

// A synthetic radar at (latDeg, lonDeg) with its storm at (stormLatDeg, stormLonDeg).
Result<Radar> makeRadar(const fs::path& dir, int index, double latDeg, double lonDeg, double stormLatDeg,
                        double stormLonDeg) {
  volume::SyntheticRadarOptions o;
  o.siteId =
      std::string("S").append(std::to_string(index));  // append: GCC 12 -Wrestrict false positive on "S" + string
  o.siteLatDeg = latDeg;
  o.siteLonDeg = lonDeg;
  o.maxRangeMeters = 80e3;
  o.seed = static_cast<std::uint64_t>(index + 1);
  const globe::GeodesicLine g = globe::geodesicInverse(latDeg, lonDeg, stormLatDeg, stormLonDeg);
  const double az = degreesToRadians(g.azimuth1Deg);
  o.stormEastKm = g.distanceMeters / 1000.0 * std::sin(az);
  o.stormNorthKm = g.distanceMeters / 1000.0 * std::cos(az);
  const fs::path file = dir / std::string("radar").append(std::to_string(index)).append(".nc");
  if (auto s = volume::writeSyntheticCfRadial(file.string(), o); !s) return s.forwardError();
  volume::RadarLoadOptions load;
  load.useGeoid = false;  // synthetic sites: heights taken as they are
  load.buildRenderLayout = true;
  auto loaded = volume::loadRadar(file.string(), load);
  if (!loaded) return loaded.forwardError();
  Radar r;
  r.polar = std::make_unique<volume::PolarVolume>(std::move(*loaded->layout));
  auto gl = engine::RadarVolumeGL::create(*r.polar);
  if (!gl) return gl.forwardError();
  r.gl = std::move(*gl);
  return r;
}

// W: samples t_i = (i + 0.5) step inside each volume's interval and before the ellipsoid, summed
// over pixels and volumes; also the pixels crossed by at least one volume.
struct Work {
  double intervalSamples = 0.0;
  long pixelsCrossed = 0;
  double volumesPerCrossedPixel = 0.0;
};

Work predictedWork(const engine::Camera& camera, const std::vector<const volume::VolumeSampler*>& samplers,
                   double step) {
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  Work w;
  long crossings = 0;
  for (int y = 0; y < rc.heightPx; ++y)
    for (int x = 0; x < rc.widthPx; ++x) {
      const glm::dvec3 dir = volume::pixelRayDirection(rc, x + 0.5, y + 0.5);
      double tLimit = 1e300;
      if (auto hit = globe::intersectRayEllipsoid(rc.eyeEcef, dir)) tLimit = glm::dot(*hit - rc.eyeEcef, dir);
      int crossed = 0;
      for (const volume::VolumeSampler* s : samplers) {
        const volume::RayInterval span = s->rayInterval(rc.eyeEcef, dir);
        if (span.empty()) continue;
        const double a = std::max(0.0, span.tEnterMeters), b = std::min(span.tExitMeters, tLimit);
        if (!(b > a)) continue;
        const double n = std::floor(b / step - 0.5) - std::ceil(a / step - 0.5) + 1.0;
        if (n <= 0.0) continue;
        w.intervalSamples += n;
        ++crossed;
      }
      crossings += crossed;
      w.pixelsCrossed += crossed > 0;
    }
  w.volumesPerCrossedPixel = w.pixelsCrossed ? static_cast<double>(crossings) / static_cast<double>(w.pixelsCrossed)
                                             : 0.0;
  return w;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 3, frames = 3, width = 320, height = 180;
  double step = 1000.0;
  fs::path out = "out/bench";
  CLI::App app{
      "Benchmark: the cost of several volumes in one march (1, 2, 4, 8 SYNTHETIC radars stacked and apart; "
      "docs/volume-rendering.md)",
      "bench_volume_overlap"};
  app.add_option("--runs", runs, "Runs per case (median of the runs' medians; default 3)")
      ->check(benchcli::numberIn(1));
  app.add_option("--frames", frames, "Timed frames per run (median; default 3)")->check(benchcli::numberIn(1));
  app.add_option_function<std::string>(
         "--size",
         [&width, &height](const std::string& text) {
           if (!benchcli::parseSize(text, width, height))
             throw CLI::ValidationError("--size " + text + ": expected WxH, each >= 16");
         },
         "Image size (default 320x180)")
      ->type_name("WxH");
  app.add_option("--step", step, "Ray-march step (m; at least 50, default 1000)")->check(benchcli::numberIn(50.0));
  app.add_option("--out", out, "Output directory (the SYNTHETIC radars; default out/bench)");
  if (const int rc = benchcli::parse(app, argc, argv); rc >= 0) return rc;
  auto context = engine::HeadlessContextGL::create();
  if (!context) {
    std::cerr << "bench_volume_overlap: " << context.error() << "\n";
    return 1;
  }
  auto renderer = engine::VolumeRendererGL::create();
  if (!renderer) {
    std::cerr << "bench_volume_overlap: " << renderer.error() << "\n";
    return 1;
  }
  auto target = engine::FramebufferGL::create(width, height);
  if (!target) {
    std::cerr << "bench_volume_overlap: " << target.error() << "\n";
    return 1;
  }
  std::error_code ec;
  const fs::path dir = out / "overlap_volumes";
  fs::create_directories(dir, ec);
  if (ec) {
    std::cerr << "bench_volume_overlap: " << dir << ": " << ec.message() << "\n";
    return 1;
  }
  std::printf("renderer: %s\ncores: %ld\nimage %dx%d, step %.0f m, %d runs x %d frames (median of run medians)\n\n",
              (*context)->describe().c_str(), sysconf(_SC_NPROCESSORS_ONLN), width, height, step, runs, frames);

  const double centreLat = 35.0, centreLon = -98.0;
  // Stacked: on a 40 km circle around the centre; apart: a row 250 km apart, centred on it.
  std::vector<Radar> stacked, apart;
  for (int k = 0; k < 8; ++k) {
    const globe::GeodesicPoint p = globe::geodesicDirect(centreLat, centreLon, 45.0 * k, 40e3);
    auto r = makeRadar(dir, k, p.latDeg, p.lonDeg, centreLat, centreLon);
    if (!r) {
      std::cerr << "bench_volume_overlap: " << r.error() << "\n";
      return 1;
    }
    stacked.push_back(std::move(*r));
  }
  for (int k = 0; k < 8; ++k) {
    const globe::GeodesicPoint p = globe::geodesicDirect(centreLat, centreLon, 90.0, (k - 3.5) * 250e3);
    // Storm 30 km north of each site.
    const globe::GeodesicPoint s = globe::geodesicDirect(p.latDeg, p.lonDeg, 0.0, 30e3);
    auto r = makeRadar(dir, 8 + k, p.latDeg, p.lonDeg, s.latDeg, s.lonDeg);
    if (!r) {
      std::cerr << "bench_volume_overlap: " << r.error() << "\n";
      return 1;
    }
    apart.push_back(std::move(*r));
  }
  // Stacked: from 150 km south of the centre, 40 km up, looking north 12 deg down.
  const globe::GeodesicPoint eye = globe::geodesicDirect(centreLat, centreLon, 180.0, 150e3);
  const engine::Camera stackedCamera(engine::CameraPose{eye.latDeg, eye.lonDeg, 40e3, 0.0, -12.0, 0.0}, 50.0, width,
                                     height);
  // Apart: straight down on the row from 2,500 km.
  const engine::Camera apartCamera(engine::CameraPose{centreLat, centreLon, 2.5e6, 0.0, -90.0, 0.0}, 50.0, width,
                                   height);

  std::printf(
      "| layout | volumes | pixels crossed | volumes per crossed pixel | interval samples (M) | "
      "frame, skipping (ms) | frame, no skipping (ms) | no skipping: ms per M interval samples | "
      "no skipping: time / N=1 time |\n|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& [name, radars, camera] :
       {std::tuple{"stacked", &stacked, &stackedCamera}, std::tuple{"apart", &apart, &apartCamera}}) {
    double baseline = 0.0;
    for (int n : {1, 2, 4, 8}) {
      std::vector<const volume::VolumeSampler*> samplers;
      std::vector<engine::VolumeLayerGL> layers, layersNoSkip;
      for (int k = 0; k < n; ++k) {
        const engine::RadarVolumeGL* gl = (*radars)[static_cast<std::size_t>(k)].gl.get();
        samplers.push_back(&gl->referenceSampler());
        engine::VolumeRenderOptions o;
        o.render.stepMeters = step;
        o.render.transfer = volume::defaultReflectivityTransfer();
        layers.push_back({gl, o});
        o.skipEmptySpace = false;
        layersNoSkip.push_back({gl, o});
      }
      const Work w = predictedWork(*camera, samplers, step);
      std::vector<double> skipRuns, fullRuns;
      for (int r = 0; r < runs; ++r) {
        skipRuns.push_back(bench::timeLayersGL(**renderer, *camera, layers, **target, frames));
        fullRuns.push_back(bench::timeLayersGL(**renderer, *camera, layersNoSkip, **target, frames));
      }
      const double skipMs = bench::median(skipRuns), fullMs = bench::median(fullRuns);
      if (n == 1) baseline = fullMs;
      std::printf("| %s | %d | %ld | %.2f | %.2f | %.1f | %.1f | %.2f | %.2f |\n", name, n, w.pixelsCrossed,
                  w.volumesPerCrossedPixel, w.intervalSamples / 1e6, skipMs, fullMs, fullMs / (w.intervalSamples / 1e6),
                  fullMs / baseline);
      std::fflush(stdout);
    }
  }
  return 0;
}
