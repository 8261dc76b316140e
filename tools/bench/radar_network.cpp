// Benchmark (a program, not a test): a radar network drawn as one volume (engine::RadarNetworkGL)
// as it grows from one radar to every WSR-88D site.
//
//   build/tools/bench/bench_radar_network [--runs N] [--frames N] [--counts 1,10,40,160]
//       [--sizes 320x180,1280x720] [--gate M] [--separate-max N] [--skip 0|1] [--samples-per-cell N]
//       [--views continental,regional] [--far-field 0|1] [--out DIR] [--data DIR]
//       (--help: the options, their defaults and bounds)
//
// The radars: SYNTHETIC volumes of one storm field (volume::syntheticNetworkStorms, seed 1; VCP 212
// angles, 360 rays, gates of --gate m to 230 km) at the NEXRAD sites of the built-in table nearest
// KTLX: 1 (KTLX), 10, 40, and 160 (every site of the table, 159). Written once under
// DIR/network_volumes. Two views: "continental" (above the central US, 4500 km up, looking down)
// and "regional" (200 km south-west of KTLX, 60 km up, looking north-east). Per count, view and
// size: the median frame time (glFinish per frame, the rays ended at the ellipsoid as the globe
// would end them; median of --frames frames per run, then of --runs runs) of the network under the mean rule with
// empty-space skipping (one volume per cluster of radars whose clip spheres meet: RadarNetworkGL::createByCluster),
// against the one-radar scene of the same view; the samples a frame takes inside the network's ray interval and the
// radars each one visits (the coverage index's list at the sample: computed on the CPU from the
// same index, the cost rule); GPU memory; the time to read the files and upload the network. Up to
// --separate-max radars (default 10) also as separate volumes (the march's rule for overlapping
// volumes: one cluster of up to 8 volumes per pass), for comparison. --samples-per-cell N > 0:
// every volume follows the step rule (volume/StepRule.h) at N samples per cell; the samples and
// visits columns count the fixed step's samples, so they are left out then. --far-field 1: each
// case is drawn again with the far field on (engine/FarFieldGL.h, FarField::Auto), timed in the same
// run, with the first frame (which makes the slabs), the far field without its mask's skipping
// (timed just before), and the mean difference of the far field's
// frame from the marched one (8-bit RGB): a second table; both frames are written to
// OUT/far_field/N_VIEW_WxH_{marched,far_field}.png.
//
// Then the rules on real data, when --data DIR (default ../shared/data) holds the overlapping
// Belgian pair (radar_odim/bewid.pvol.hdf and behel_loop/20200207130000...dbzh.scanz.hdf, DBZH):
// the frame time of each overlap rule (mean, lowest, max as one network; integrate as the two
// radars apart) above the pair, against Wideumont alone, at each size.
#include <atmoglobe/bench/GridViews.h>
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/RadarNetworkGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/RenderCamera.h>
#include <atmoglobe/volume/StationList.h>
#include <atmoglobe/volume/SyntheticRadar.h>
#include <atmoglobe/volume/TransferFunction.h>

#include "BenchCli.h"

#include <epoxy/gl.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using namespace atmoglobe;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The median over `runs` runs of the median frame time of each.
double timeFrames(engine::VolumeRendererGL& renderer, const engine::Camera& camera,
                  const std::vector<engine::VolumeLayerGL>& layers, const engine::FramebufferGL& target, int frames,
                  int runs, const std::vector<float>& depth) {
  std::vector<double> runMedians;
  for (int r = 0; r < runs; ++r)
    runMedians.push_back(bench::timeLayersGL(renderer, camera, layers, target, frames, &depth));
  return bench::median(runMedians);
}

// The samples a frame takes inside the network's ray interval (before the ellipsoid) and the
// radars their coverage cells list, summed over pixels.
struct Visits {
  double samples = 0.0, visits = 0.0;
  std::size_t maxListed = 0;
};

Visits countVisits(const engine::Camera& camera, const volume::RadarNetworkSampler& net, double step) {
  const volume::RenderCamera rc = engine::referenceCameraFor(camera);
  Visits v;
  for (int y = 0; y < rc.heightPx; ++y)
    for (int x = 0; x < rc.widthPx; ++x) {
      const glm::dvec3 dir = volume::pixelRayDirection(rc, x + 0.5, y + 0.5);
      double tLimit = 1e300;
      if (auto hit = globe::intersectRayEllipsoid(rc.eyeEcef, dir)) tLimit = glm::dot(*hit - rc.eyeEcef, dir);
      const volume::RayInterval span = net.rayInterval(rc.eyeEcef, dir);
      if (span.empty()) continue;
      const double a = std::max(0.0, span.tEnterMeters), b = std::min(span.tExitMeters, tLimit);
      for (double i = std::ceil(a / step - 0.5); (i + 0.5) * step <= b; i += 1.0) {
        const auto [first, last] = net.coverage().radarsAt(rc.eyeEcef + (i + 0.5) * step * dir);
        const std::size_t n = static_cast<std::size_t>(last - first);
        v.samples += 1.0;
        v.visits += static_cast<double>(n);
        v.maxListed = std::max(v.maxListed, n);
      }
    }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 3, frames = 3, separateMax = 10;
  bool skip = true, farField = false;
  double gateMeters = 1000.0, samplesPerCell = 0.0;
  std::vector<int> counts = {1, 10, 40, 160};
  std::string viewNames = "continental,regional";
  std::vector<std::pair<int, int>> sizes = {{320, 180}, {1280, 720}};
  fs::path out = "out/bench";
  fs::path data = "../shared/data";
  CLI::App app{
      "Benchmark: a radar network drawn as one volume as it grows from one radar to every WSR-88D site "
      "(frame time, samples, radars visited per sample, GPU memory, read time; docs/networks.md)",
      "bench_radar_network"};
  app.add_option("--runs", runs, "Runs per case (median of the runs' medians; default 3)")
      ->check(benchcli::numberIn(1));
  app.add_option("--frames", frames, "Timed frames per run (median; default 3)")->check(benchcli::numberIn(1));
  app.add_option_function<std::string>(
         "--counts",
         [&counts](const std::string& text) {
           std::vector<int> list;
           std::stringstream s(text);
           std::string item;
           while (std::getline(s, item, ',')) {
             int n = 0;
             const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), n);
             if (item.empty() || error != std::errc{} || end != item.data() + item.size() || n < 1)
               throw CLI::ValidationError("--counts " + text + ": expected positive numbers N,N,...");
             list.push_back(n);
           }
           if (list.empty()) throw CLI::ValidationError("--counts " + text + ": expected positive numbers N,N,...");
           counts = std::move(list);
         },
         "Radar counts, comma-separated (the sites nearest KTLX; default 1,10,40,160)")
      ->type_name("N,N,...");
  benchcli::addSizesOption(app, sizes, "Image sizes, comma-separated (default 320x180,1280x720)");
  app.add_option("--gate", gateMeters, "Gate spacing of the SYNTHETIC radars (m; at least 50, default 1000)")
      ->check(benchcli::numberIn(50.0));
  app.add_option("--separate-max", separateMax,
                 "Counts up to this many radars also drawn as separate volumes (default 10; 0: none)");
  app.add_option("--skip", skip, "Empty-space skipping, 0 or 1 (default 1)")->type_name("0|1");
  app.add_option("--samples-per-cell", samplesPerCell,
                 "> 0: every volume follows the step rule at N samples per cell (0 to 64, default 0: the fixed step)")
      ->check(benchcli::numberIn(0.0, 64.0));
  app.add_option("--views", viewNames, "Views, comma-separated: continental, regional (default both)")
      ->type_name("NAME,...");
  app.add_option("--far-field", farField,
                 "1: each case also drawn with the far field on (FarFieldGL.h), a second table (default 0)")
      ->type_name("0|1");
  app.add_option("--out", out, "Output directory (the SYNTHETIC volumes under DIR/network_volumes; default out/bench)");
  app.add_option("--data", data,
                 "Directory holding the Belgian pair for the overlap rules on real data (default ../shared/data)");
  if (const int rc = benchcli::parse(app, argc, argv); rc >= 0) return rc;
  auto context = engine::HeadlessContextGL::create();
  if (!context) {
    std::cerr << "bench_radar_network: " << context.error() << "\n";
    return 1;
  }
  auto renderer = engine::VolumeRendererGL::create();
  if (!renderer) {
    std::cerr << "bench_radar_network: " << renderer.error() << "\n";
    return 1;
  }

  // The sites nearest KTLX, all of them for the largest count.
  std::vector<volume::Station> sites = volume::builtinNexradSites();
  const volume::Station* ktlx = volume::findStation(sites, "KTLX");
  if (!ktlx || sites.empty()) {
    std::cerr << "bench_radar_network: the built-in NEXRAD table has no KTLX\n";
    return 1;
  }
  const double lat0 = ktlx->latDeg, lon0 = ktlx->lonDeg;
  std::sort(sites.begin(), sites.end(), [&](const volume::Station& a, const volume::Station& b) {
    return globe::geodesicInverse(lat0, lon0, a.latDeg, a.lonDeg).distanceMeters <
           globe::geodesicInverse(lat0, lon0, b.latDeg, b.lonDeg).distanceMeters;
  });
  const std::size_t maxCount =
      std::min<std::size_t>(sites.size(), static_cast<std::size_t>(*std::max_element(counts.begin(), counts.end())));
  sites.resize(maxCount);

  // The volumes, written once.
  const fs::path dir = out / "network_volumes";
  std::error_code ec;
  fs::create_directories(dir, ec);
  volume::SyntheticRadarOptions base;
  base.gateSpacingMeters = gateMeters;
  base.firstGateRangeMeters = std::max(gateMeters, 2125.0);
  std::vector<std::pair<double, double>> latLon;
  for (const auto& s : volume::builtinNexradSites()) latLon.emplace_back(s.latDeg, s.lonDeg);
  base.networkStorms = volume::syntheticNetworkStorms(latLon, 230.0 + 250.0, 1);
  std::vector<std::string> files(maxCount);
  {
    const auto t0 = Clock::now();
    std::atomic<std::size_t> next{0};
    std::atomic<int> failed{0};
    std::vector<std::thread> pool;
    for (unsigned w = 0; w < std::max(1u, std::thread::hardware_concurrency()); ++w)
      pool.emplace_back([&] {
        for (std::size_t i = next++; i < maxCount; i = next++) {
          const volume::Station& s = sites[i];
          files[i] = (dir / (s.id + "_g" + std::to_string(static_cast<int>(gateMeters)) + ".nc")).string();
          if (fs::exists(files[i])) continue;
          volume::SyntheticRadarOptions o = base;
          o.siteId = s.id;
          o.siteLatDeg = s.latDeg;
          o.siteLonDeg = s.lonDeg;
          o.antennaAltitudeMslMeters = s.elevationMeters + s.towerHeightMeters.value_or(0.0);
          if (auto st = volume::writeSyntheticCfRadial(files[i], o); !st) {
            std::cerr << "bench_radar_network: " << st.error() << "\n";
            ++failed;
          }
        }
      });
    for (auto& t : pool) t.join();
    if (failed) return 1;
    std::fprintf(stderr, "volumes ready in %.1f s (%zu sites, %zu storms)\n", secondsSince(t0), maxCount,
                 base.networkStorms.size());
  }

  std::printf(
      "renderer: %s\ncores: %ld\nstep %.0f m (default), samples per cell %g (0: the fixed step), gates %.0f m, "
      "empty-space skipping %s, %d runs x %d frames (median of run medians)\n\n",
      (*context)->describe().c_str(), sysconf(_SC_NPROCESSORS_ONLN), volume::VolumeRenderSettings{}.stepMeters,
      samplesPerCell, gateMeters, skip ? "on" : "off", runs, frames);
  struct View {
    const char* name;
    engine::CameraPose pose;
  };
  const globe::GeodesicPoint sw = globe::geodesicDirect(lat0, lon0, 225.0, 200e3);
  std::vector<View> views;
  for (const View& v : {View{"continental", {38.5, -97.0, 4.5e6, 0.0, -90.0, 0.0}},
                        View{"regional", {sw.latDeg, sw.lonDeg, 6e4, 45.0, -15.0, 0.0}}})
    if (("," + viewNames + ",").find("," + std::string(v.name) + ",") != std::string::npos) views.push_back(v);
  if (views.empty()) {
    std::cerr << "bench_radar_network: --views " << viewNames << ": expected continental and/or regional\n";
    return 2;
  }
  engine::VolumeRenderOptions options;
  options.render.transfer = volume::defaultReflectivityTransfer();
  options.skipEmptySpace = skip;
  options.render.samplesPerCell = samplesPerCell;

  std::printf(
      "| radars | view | size | network frame (ms) | / 1 radar | separate volumes (ms) | samples (M) | radars "
      "visited per sample (mean, max) | GPU MB | read + upload (s) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<double> oneRadar(views.size() * sizes.size(), 0.0);
  std::vector<double> oneRadarFar(views.size() * sizes.size(), 0.0);
  std::ostringstream farTable;
  std::vector<std::shared_ptr<const volume::PolarVolume>> loaded;
  double readSeconds = 0.0;
  for (int count : counts) {
    const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(count), maxCount);
    const auto t0 = Clock::now();
    while (loaded.size() < n) {
      volume::RadarLoadOptions load;
      load.buildRenderLayout = true;
      auto r = volume::loadRadar(files[loaded.size()], load);
      if (!r) {
        std::cerr << "bench_radar_network: " << r.error() << "\n";
        return 1;
      }
      loaded.push_back(std::make_shared<const volume::PolarVolume>(std::move(*r->layout)));
    }
    readSeconds += secondsSince(t0);
    const auto t1 = Clock::now();
    std::vector<std::shared_ptr<const volume::PolarVolume>> radars(loaded.begin(),
                                                                   loaded.begin() + static_cast<std::ptrdiff_t>(n));
    auto network = engine::RadarNetworkGL::createByCluster(radars, volume::OverlapRule::WeightedMean,
                                                           volume::FieldKind::Reflectivity);
    if (!network) {
      std::cerr << "bench_radar_network: " << network.error() << "\n";
      return 1;
    }
    const double uploadSeconds = secondsSince(t1);
    std::vector<std::unique_ptr<engine::RadarVolumeGL>> separate;
    if (count <= separateMax)
      for (const auto& r : radars) {
        auto gl = engine::RadarVolumeGL::create(*r);
        if (!gl) {
          std::cerr << "bench_radar_network: " << gl.error() << "\n";
          return 1;
        }
        separate.push_back(std::move(*gl));
      }
    for (std::size_t v = 0; v < views.size(); ++v)
      for (std::size_t s = 0; s < sizes.size(); ++s) {
        const engine::Camera camera(views[v].pose, 60.0, sizes[s].first, sizes[s].second);
        // The rays end at the ground, as the globe ends them (without it, the continental view's
        // march drew radars of Korea and Okinawa through the Earth).
        const std::vector<float> depth = bench::ellipsoidDepth(camera);
        auto target = engine::FramebufferGL::create(sizes[s].first, sizes[s].second);
        if (!target) {
          std::cerr << "bench_radar_network: " << target.error() << "\n";
          return 1;
        }
        std::vector<engine::VolumeLayerGL> networkLayers;
        std::size_t gpuBytes = 0;
        for (const auto& c : *network) {
          networkLayers.push_back({c.get(), options});
          gpuBytes += c->gpuBytes();
        }
        const double ms = timeFrames(**renderer, camera, networkLayers, **target, frames, runs, depth);
        if (count == counts.front()) oneRadar[v * sizes.size() + s] = ms;
        std::string separateMs = "-";
        if (!separate.empty()) {
          std::vector<engine::VolumeLayerGL> layers;
          for (const auto& g : separate) layers.push_back({g.get(), options});
          char b[32];
          std::snprintf(b, sizeof b, "%.2f", timeFrames(**renderer, camera, layers, **target, frames, runs, depth));
          separateMs = b;
        }
        // The visits at the smaller size only (the CPU walks every sample).
        std::string visits = "-", samples = "-";
        if (s == 0 && samplesPerCell <= 0.0) {
          Visits c;
          for (const auto& cluster : *network) {
            const Visits one = countVisits(camera, cluster->network(), options.render.stepMeters);
            c.samples += one.samples;
            c.visits += one.visits;
            c.maxListed = std::max(c.maxListed, one.maxListed);
          }
          char b[64];
          std::snprintf(b, sizeof b, "%.2f, %zu", c.samples > 0 ? c.visits / c.samples : 0.0, c.maxListed);
          visits = b;
          std::snprintf(b, sizeof b, "%.2f", c.samples / 1e6);
          samples = b;
        }
        std::printf("| %zu | %s | %dx%d | %.2f | %.2f | %s | %s | %s | %.0f | %.1f |\n", n, views[v].name,
                    sizes[s].first, sizes[s].second, ms, ms / oneRadar[v * sizes.size() + s], separateMs.c_str(),
                    samples.c_str(), visits.c_str(), static_cast<double>(gpuBytes) / 1e6, readSeconds + uploadSeconds);
        std::fflush(stdout);
        if (farField) {
          const globe::ImageRGBA8 marched = (*target)->readColor();
          std::vector<engine::VolumeLayerGL> farLayers = networkLayers;
          for (engine::VolumeLayerGL& l : farLayers) l.options.farField = engine::FarField::Auto;
          const std::size_t madeBefore = (*renderer)->farField().slabSetsMade();
          const auto tFirst = Clock::now();
          bench::uploadDepthGL(**target, depth);
          bench::clearTargetGL(**target, &depth);
          (*renderer)->draw(camera, farLayers, **target);
          glFinish();
          const double firstMs = secondsSince(tFirst) * 1e3;
          const std::size_t made = (*renderer)->farField().slabSetsMade() - madeBefore;
          // Every pixel visiting the slabs, without the mask's skipping, timed just before it.
          (*renderer)->farField().setMaskSkipping(false);
          const double unmaskedMs = timeFrames(**renderer, camera, farLayers, **target, frames, runs, depth);
          (*renderer)->farField().setMaskSkipping(true);
          const double farMs = timeFrames(**renderer, camera, farLayers, **target, frames, runs, depth);
          if (count == counts.front()) oneRadarFar[v * sizes.size() + s] = farMs;
          const globe::ImageRGBA8 far = (*target)->readColor();
          // Both frames, to look at: OUT/far_field/N_VIEW_WxH_{marched,far_field}.png.
          const fs::path pictures = out / "far_field";
          fs::create_directories(pictures, ec);
          const std::string stem = (pictures / (std::to_string(n) + "_" + views[v].name + "_" +
                                                std::to_string(sizes[s].first) + "x" + std::to_string(sizes[s].second)))
                                       .string();
          (void)globe::writePng(stem + "_marched.png", marched);
          (void)globe::writePng(stem + "_far_field.png", far);
          double sum = 0.0;
          int maxDiff = 0;
          for (std::size_t i = 0; i < far.pixels.size(); ++i)
            if (i % 4 != 3) {
              const int d = std::abs(int(far.pixels[i]) - int(marched.pixels[i]));
              sum += d;
              maxDiff = std::max(maxDiff, d);
            }
          char row[320];
          std::snprintf(
              row, sizeof row, "| %zu | %s | %dx%d | %.2f | %.2f | %.2f | %.1fx | %.2f | %zu | %.3f | %d | %.0f |\n", n,
              views[v].name, sizes[s].first, sizes[s].second, ms, unmaskedMs, farMs, ms / farMs,
              farMs / oneRadarFar[v * sizes.size() + s], made, sum / static_cast<double>(far.pixels.size() / 4 * 3),
              maxDiff, static_cast<double>((*renderer)->farField().gpuBytes()) / 1e6);
          farTable << row << "  (first frame, slabs made: " << firstMs << " ms)\n";
        }
      }
  }

  if (farField) {
    std::printf(
        "\nThe far field (FarField::Auto) against the march, same run\n\n| radars | view | size | marched (ms) | far "
        "field, no mask (ms) | far field (ms) | faster | / 1 radar (far field) | slab sets made | mean abs vs marched "
        "(8-bit RGB) | max | slabs kept (MB) |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n%s",
        farTable.str().c_str());
    std::fflush(stdout);
  }

  // The rules on the real Belgian pair.
  const fs::path wid = data / "radar_odim/bewid.pvol.hdf";
  const fs::path hel = data / "radar_odim/behel_loop/20200207130000.rad.behel.pvol.dbzh.scanz.hdf";
  if (!fs::exists(wid) || !fs::exists(hel)) {
    std::printf("\n(the Belgian pair is not under %s: its rules are not timed)\n", data.string().c_str());
    return 0;
  }
  std::vector<std::shared_ptr<const volume::PolarVolume>> pair;
  for (const fs::path& path : {wid, hel}) {
    volume::RadarLoadOptions load;
    load.buildRenderLayout = true;
    auto r = volume::loadRadar(path.string(), load);
    if (!r) {
      std::cerr << "bench_radar_network: " << r.error() << "\n";
      return 1;
    }
    pair.push_back(std::make_shared<const volume::PolarVolume>(std::move(*r->layout)));
  }
  std::vector<std::unique_ptr<engine::RadarVolumeGL>> apart;
  for (const auto& r : pair) {
    auto gl = engine::RadarVolumeGL::create(*r);
    if (!gl) {
      std::cerr << "bench_radar_network: " << gl.error() << "\n";
      return 1;
    }
    apart.push_back(std::move(*gl));
  }
  std::printf(
      "\nBelgian pair (bewid DBZH 2019-06-06 00:00Z, behel DBZH 2020-02-07 13:00Z; 128 km apart), 300 km above "
      "the middle looking down\n\n| rule | size | frame (ms) | / Wideumont alone |\n|---|---|---|---|\n");
  for (const auto& [w, h] : sizes) {
    const engine::Camera camera(engine::CameraPose{50.5, 5.45, 3e5, 0.0, -90.0, 0.0}, 60.0, w, h);
    const std::vector<float> depth = bench::ellipsoidDepth(camera);
    auto target = engine::FramebufferGL::create(w, h);
    if (!target) {
      std::cerr << "bench_radar_network: " << target.error() << "\n";
      return 1;
    }
    const double alone = timeFrames(**renderer, camera, {{apart[0].get(), options}}, **target, frames, runs, depth);
    for (auto rule : {volume::OverlapRule::WeightedMean, volume::OverlapRule::LowestBeam, volume::OverlapRule::Maximum,
                      volume::OverlapRule::Integrate}) {
      double ms = 0.0;
      if (rule == volume::OverlapRule::Integrate) {
        ms = timeFrames(**renderer, camera, {{apart[0].get(), options}, {apart[1].get(), options}}, **target, frames,
                        runs, depth);
      } else {
        auto network = engine::RadarNetworkGL::create(pair, rule, volume::FieldKind::Reflectivity);
        if (!network) {
          std::cerr << "bench_radar_network: " << network.error() << "\n";
          return 1;
        }
        ms = timeFrames(**renderer, camera, {{network->get(), options}}, **target, frames, runs, depth);
      }
      std::printf("| %s | %dx%d | %.2f | %.2f |\n", volume::toString(rule), w, h, ms, ms / alone);
      std::fflush(stdout);
    }
  }
  return 0;
}
