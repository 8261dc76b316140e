#include <atmoglobe/bench/VtkPeer.h>

#include <atmoglobe/bench/Format.h>
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/bench/Process.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/TransferFunction.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>
#include <system_error>

namespace atmoglobe::bench {

namespace fs = std::filesystem;

namespace {

nlohmann::json transferJson(const volume::TransferFunction& tf) {
  nlohmann::json colors = nlohmann::json::array();
  const auto& stops = tf.colors.stops();
  for (std::size_t i = 0; i < stops.size(); ++i) {
    const auto& s = stops[i];
    const double v0 = (s.value - tf.colors.offset()) / tf.colors.scale();
    colors.push_back({v0, s.start.r / 255.0, s.start.g / 255.0, s.start.b / 255.0});
    if (i + 1 < stops.size()) {
      const double v1 = (stops[i + 1].value - tf.colors.offset()) / tf.colors.scale();
      colors.push_back({v1 - 1e-2, s.end.r / 255.0, s.end.g / 255.0, s.end.b / 255.0});
    }
  }
  return {{"colors", colors},
          {"opacity", {{tf.opacityZeroValue, 0.0}, {tf.opacityFullValue, tf.maxOpacity}}},
          {"unit_distance_m", tf.opacityReferenceMeters}};
}

/// The job the script reads: the grid, the transfer function, the views in the site's ENU frame.
nlohmann::json peerJob(const BenchVolume& v, const std::vector<BenchView>& views, const PeerGrid& g,
                       const fs::path& raw, const fs::path& dir, const volume::TransferFunction& transfer,
                       const PeerSettings& settings) {
  const int w = settings.widthPx, h = settings.heightPx;
  nlohmann::json job;
  job["grid"] = {{"file", fs::absolute(raw).string()},
                 {"dims", {g.nx, g.ny, g.nz}},
                 {"spacing_m", g.spacingMeters},
                 {"origin_enu_m", {g.originEnu.x, g.originEnu.y, g.originEnu.z}}};
  job["transfer"] = transferJson(transfer);
  job["frames"] = settings.frames;
  job["sample_distance_m"] = g.spacingMeters;
  job["out_dir"] = fs::absolute(dir).string();
  const glm::dmat3 enu = globe::enuAxes(v.polar.site.latDeg, v.polar.site.lonDeg);
  const glm::dvec3 site =
      globe::geodeticToEcef({v.polar.site.latDeg, v.polar.site.lonDeg, v.polar.site.antennaHeightEllipsoidMeters});
  nlohmann::json jviews = nlohmann::json::array();
  for (const BenchView& view : views) {
    if (view.volume != &v) continue;
    const engine::Camera cam(view.pose, view.fovYDeg, w, h);
    const glm::dvec3 eye = glm::transpose(enu) * (cam.eyeEcef() - site);
    const glm::dvec3 fwd = glm::transpose(enu) * cam.forwardEcef();
    const glm::dvec3 up = glm::transpose(enu) * cam.upEcef();
    jviews.push_back({{"name", view.name},
                      {"width", w},
                      {"height", h},
                      {"position", {eye.x, eye.y, eye.z}},
                      {"focal_point", {eye.x + 1e4 * fwd.x, eye.y + 1e4 * fwd.y, eye.z + 1e4 * fwd.z}},
                      {"view_up", {up.x, up.y, up.z}},
                      {"fov_y_deg", view.fovYDeg}});
  }
  job["views"] = jviews;
  return job;
}

}  // namespace

std::string findPeerScript(const std::string& explicitPath) {
  if (!explicitPath.empty()) return explicitPath;
  std::vector<fs::path> candidates = {"tools/bench/vtk_peer.py"};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (fs::path d = exe.parent_path(); !d.empty() && d != d.parent_path(); d = d.parent_path())
      candidates.push_back(d / "tools/bench/vtk_peer.py");
  }
  for (const fs::path& c : candidates)
    if (fs::exists(c, ec)) return c.string();
  return {};
}

std::string peerUnavailableReason(const std::string& script) {
  const bool haveVtk = runProgram({"/usr/bin/python3", "-c", "import vtk"}, true).succeeded();
  const bool haveNumpy = runProgram({"/usr/bin/python3", "-c", "import numpy"}, true).succeeded();
  const bool haveXvfb = !findProgram("xvfb-run").empty();
  if (!haveVtk) return "python3-vtk9 is not installed";
  if (!haveNumpy) return "python3-numpy is not installed (vtk_peer.py needs it)";
  if (!haveXvfb) return "xvfb-run is missing";
  if (script.empty()) return "tools/bench/vtk_peer.py not found";
  return {};
}

Result<PeerSection> runVtkPeer(const std::vector<std::unique_ptr<BenchVolume>>& volumes,
                               const std::vector<BenchView>& views, const PeerSettings& settings, ReferenceStore& refs,
                               std::ostream& log) {
  PeerSection out;
  if (const std::string why = peerUnavailableReason(settings.script); !why.empty()) {
    out.note = "peer skipped: " + why + " (install with: sudo apt-get install python3-vtk9 python3-numpy xvfb)";
    return out;
  }
  const int w = settings.widthPx, h = settings.heightPx;
  std::error_code ec;
  for (const auto& v : volumes) {
    const auto transfer = volume::defaultReflectivityTransfer();
    std::vector<float> grid;
    log << "peer: resampling " << v->key << " to a Cartesian grid ..." << std::flush;
    PeerGrid g = buildPeerGrid(v->polar, transfer.opacityZeroValue, transfer.opacityZeroValue, settings.maxVoxels,
                               settings.threads, &grid);
    if (g.nx == 0) continue;
    log << " " << g.nx << "x" << g.ny << "x" << g.nz << " at " << g.spacingMeters << " m, "
        << formatG(g.resampleSeconds, 3) << " s\n";
    const fs::path dir = settings.outDir / "peer";
    fs::create_directories(dir, ec);
    const fs::path raw = dir / (v->key + "-grid.f32");
    {
      std::ofstream file(raw, std::ios::binary);
      file.write(reinterpret_cast<const char*>(grid.data()), static_cast<std::streamsize>(grid.size() * sizeof(float)));
      if (!file) return makeError(raw.string() + ": cannot write the peer grid");
    }
    grid.clear();
    grid.shrink_to_fit();
    const fs::path jobFile = dir / (v->key + "-job.json");
    std::ofstream(jobFile) << peerJob(*v, views, g, raw, dir, transfer, settings).dump(2);
    const fs::path resultFile = dir / (v->key + "-result.json");
    fs::remove(resultFile, ec);
    // No shell: the paths go to the programs as they are, whatever characters they hold.
    const std::vector<std::string> argv = {"xvfb-run",
                                           "-a",
                                           "-s",
                                           "-screen 0 1280x1024x24",
                                           "/usr/bin/python3",
                                           settings.script,
                                           fs::absolute(jobFile).string(),
                                           fs::absolute(resultFile).string()};
    log << "peer: " << displayCommand(argv) << "\n" << std::flush;
    const ProgramExit exit = runProgram(argv);
    out.grids[v->key] = g;
    std::ifstream rin(resultFile);
    if (!exit.succeeded()) {
      // The script rewrites its result after every mapper and view, so what finished before
      // a crash (VTK aborts the process, e.g. on a lost X connection) is still reported.
      out.note += "VTK peer for " + v->key + " failed (" + exit.describe() + ")" +
                  (rin ? "; the runs that finished before are below" : "") + "; ";
    }
    if (!rin) continue;
    nlohmann::json res;
    try {
      rin >> res;
    } catch (const std::exception& e) {
      out.note += resultFile.string() + ": " + e.what() + "; ";
      continue;
    }
    for (const auto& r : res["runs"]) {
      PeerResult pr;
      pr.view = r.value("view", "");
      pr.mapper = r.value("mapper", "");
      pr.medianMs = r.value("median_ms", 0.0);
      pr.peakRssMb = res.value("peak_rss_mb", 0.0);
      pr.note = r.value("note", "");
      const std::string png = r.value("image", "");
      const BenchView* view = nullptr;
      for (const BenchView& bv : views)
        if (bv.name == pr.view) view = &bv;
      auto img = globe::decodeImageFile(png);
      if (view && img && img->width == w && img->height == h) {
        const volume::VolumeImage ref =
            refs.get(*view, w, h, referenceSettings(volume::VolumeRenderMode::Dvr, settings.referenceStepMeters));
        pr.error = volume::compareImages(fromRgba8(*img), ref);
        pr.ok = true;
      } else {
        pr.note += " (no image)";
      }
      out.results.push_back(pr);
    }
  }
  return out;
}

}  // namespace atmoglobe::bench
