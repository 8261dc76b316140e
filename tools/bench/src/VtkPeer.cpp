#include <atmoglobe/bench/VtkPeer.h>

#include <atmoglobe/bench/Format.h>
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/bench/Process.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/GridVolumeGL.h>
#include <atmoglobe/globe/AtomicFile.h>
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
nlohmann::json peerJob(const std::vector<const BenchView*>& views, const PeerFrame& frame, const PeerGrid& g,
                       const fs::path& raw, const fs::path& dir, const volume::TransferFunction& transfer,
                       const PeerSettings& settings, bool occludeByEllipsoid) {
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
  const glm::dmat3& enu = frame.enuToEcef;
  const glm::dvec3& site = frame.originEcef;
  if (occludeByEllipsoid) {
    // The Earth as an opaque black ellipsoid (the reference stops at the ellipsoid, ours gets its
    // depth): in frame coordinates p = R^T (diag(a, a, b) u - origin), u on the unit sphere.
    const glm::dmat3 rt = glm::transpose(enu);
    const glm::dvec3 c = -(rt * site);
    nlohmann::json m = nlohmann::json::array();
    const double radii[3] = {globe::kWgs84A, globe::kWgs84A, globe::kWgs84B};
    for (int r = 0; r < 3; ++r) {
      for (int col = 0; col < 3; ++col) m.push_back(rt[col][r] * radii[col]);  // glm: [column][row]
      m.push_back(c[r]);
    }
    for (double x : {0.0, 0.0, 0.0, 1.0}) m.push_back(x);
    job["ellipsoid_matrix"] = m;  // row-major 4x4
  }
  nlohmann::json jviews = nlohmann::json::array();
  for (const BenchView* vp : views) {
    const BenchView& view = *vp;
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

namespace {

/// Writes the grid and the job, runs the script, reads its result and compares its images with
/// the references (DVR, same size, the volume's transfer function) into `out`.
Status runPeerJob(const std::string& key, const PeerGrid& g, std::vector<float>& grid,
                  const std::vector<const BenchView*>& views, const PeerFrame& frame,
                  const volume::TransferFunction& transfer, const PeerSettings& settings, bool occludeByEllipsoid,
                  ReferenceStore& refs, std::ostream& log, PeerSection& out) {
  const int w = settings.widthPx, h = settings.heightPx;
  std::error_code ec;
  const fs::path dir = settings.outDir / "peer";
  fs::create_directories(dir, ec);
  const fs::path raw = dir / (key + "-grid.f32");
  // Through the atomic helper like every output: a killed bench never leaves a short grid for
  // the next peer run to read.
  if (Status s = globe::writeFileAtomic(
          raw.string(), std::string_view(reinterpret_cast<const char*>(grid.data()), grid.size() * sizeof(float)));
      !s) {
    return makeError(raw.string() + ": cannot write the peer grid: " + s.error());
  }
  grid.clear();
  grid.shrink_to_fit();
  const fs::path jobFile = dir / (key + "-job.json");
  if (Status s = globe::writeFileAtomic(
          jobFile.string(), peerJob(views, frame, g, raw, dir, transfer, settings, occludeByEllipsoid).dump(2));
      !s) {
    return s;
  }
  const fs::path resultFile = dir / (key + "-result.json");
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
  out.grids[key] = g;
  std::ifstream rin(resultFile);
  if (!exit.succeeded()) {
    // The script rewrites its result after every mapper and view, so what finished before
    // a crash (VTK aborts the process, e.g. on a lost X connection) is still reported.
    out.note += "VTK peer for " + key + " failed (" + exit.describe() + ")" +
                (rin ? "; the runs that finished before are below" : "") + "; ";
  }
  if (!rin) return Ok{};
  nlohmann::json res;
  try {
    rin >> res;
  } catch (const std::exception& e) {
    out.note += resultFile.string() + ": " + e.what() + "; ";
    return Ok{};
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
    for (const BenchView* bv : views)
      if (bv->name == pr.view) view = bv;
    auto img = globe::decodeImageFile(png);
    if (view && img && img->width == w && img->height == h) {
      const volume::VolumeImage ref = refs.get(
          *view, w, h, referenceSettings(volume::VolumeRenderMode::Dvr, settings.referenceStepMeters, transfer));
      pr.error = volume::compareImages(fromRgba8(*img), ref);
      pr.ok = true;
    } else {
      pr.note += " (no image)";
    }
    out.results.push_back(pr);
  }
  return Ok{};
}

}  // namespace

Result<PeerSection> runVtkPeer(const std::vector<std::unique_ptr<BenchVolume>>& volumes,
                               const std::vector<BenchView>& views, const PeerSettings& settings, ReferenceStore& refs,
                               std::ostream& log) {
  PeerSection out;
  if (const std::string why = peerUnavailableReason(settings.script); !why.empty()) {
    out.note = "peer skipped: " + why + " (install with: sudo apt-get install python3-vtk9 python3-numpy xvfb)";
    return out;
  }
  for (const auto& v : volumes) {
    const volume::TransferFunction& transfer = v->transfer;
    std::vector<float> grid;
    if (v->kind == VolumeKind::Radar) {
      log << "peer: resampling " << v->key << " to a Cartesian grid ..." << std::flush;
      PeerGrid g = buildPeerGrid(v->polar, transfer.opacityZeroValue, transfer.opacityZeroValue, settings.maxVoxels,
                                 settings.threads, &grid);
      if (g.nx == 0) continue;
      log << " " << g.nx << "x" << g.ny << "x" << g.nz << " at " << g.spacingMeters << " m, "
          << formatG(g.resampleSeconds, 3) << " s\n";
      std::vector<const BenchView*> mine;
      for (const BenchView& view : views)
        if (view.volume == v.get()) mine.push_back(&view);
      const PeerFrame frame =
          enuFrameAt(v->polar.site.latDeg, v->polar.site.lonDeg, v->polar.site.antennaHeightEllipsoidMeters);
      if (Status st = runPeerJob(v->key, g, grid, mine, frame, transfer, settings, false, refs, log, out); !st)
        return st.forwardError();
      continue;
    }
    // A grid: one Cartesian grid per view, of the crop the view draws (what VTK would be given
    // for that view), in the ENU frame at the crop's centre on the ellipsoid; voxels by the
    // grid's own exact sampler over the crop.
    for (const BenchView& view : views) {
      if (view.volume != v.get()) continue;
      const auto* gl = dynamic_cast<const engine::GridVolumeGL*>(view.gl.get());
      if (!gl) continue;
      const volume::GridVolume& crop = gl->grid();
      const std::size_t cj = crop.ny / 2, ci = crop.nx / 2;
      const PeerFrame frame = enuFrameAt(crop.latDegAt(cj, ci), crop.lonDegAt(cj, ci), 0.0);
      glm::dvec3 lo, hi;
      double native = 0.0;
      if (!gridPeerBox(crop, frame, transfer.opacityZeroValue, &lo, &hi, &native)) continue;
      PeerGrid g = layoutPeerGrid(lo, hi, native, settings.maxVoxels);
      log << "peer: resampling " << view.name << " to " << g.nx << "x" << g.ny << "x" << g.nz << " at "
          << formatG(g.spacingMeters, 4) << " m ..." << std::flush;
      resampleSampler(gl->referenceSampler(), frame, g, transfer.opacityZeroValue, settings.threads, &grid);
      measureReconstructionError(gl->referenceSampler(), frame, g, grid, transfer.opacityZeroValue,
                                 transfer.opacityZeroValue, 20000);
      log << " " << formatG(g.resampleSeconds, 3) << " s; trilinear error max " << formatG(g.maxReconstructionError, 3)
          << ", rms " << formatG(g.rmsReconstructionError, 3) << "\n";
      if (Status st = runPeerJob(view.name, g, grid, {&view}, frame, transfer, settings, true, refs, log, out); !st)
        return st.forwardError();
    }
  }
  return out;
}

}  // namespace atmoglobe::bench
