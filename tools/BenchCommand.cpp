// atmoglobe bench: the speed/accuracy trade of the GPU radar-volume marcher, measured.
//
// Fixed views of real volumes (../shared/data); a grid of step x image scale x interpolation x
// beam model (DVR; MIP and ISO at the default); per cell the median GPU frame time and the error
// against the CPU reference renderer (double precision, exact inverse, linear, fine step, full
// resolution, no empty-space skipping). Writes volume_bench.md / .csv / .png under --out.
// Then the side-by-side peer: the same volume resampled to a Cartesian grid and rendered by VTK
// (tools/bench/vtk_peer.py under xvfb-run), timed and compared with the same reference.
#include "Commands.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/PlotImage.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <thread>

namespace atmoglobe::tools {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct BenchOptions {
  std::string dataDir = "../shared/data";
  std::string outDir = "out/bench";
  bool quick = false;
  int frames = 7;
  double referenceStepMeters = 100.0;
  int threads = 0;  // 0: hardware concurrency
  bool peer = true;
  bool referenceOnly = false;
  std::string peerScript;
  std::vector<std::string> viewNames;  // empty: every view
  std::vector<double> stepsMeters;     // empty: the standard grid
};

// ---------------------------------------------------------------------------------------------
// Volumes and views

struct BenchVolume {
  std::string key;  ///< short name (KLBB, AU40)
  std::string path;
  volume::PolarVolume polar;
  std::unique_ptr<engine::RadarVolumeGL> gl;
};

struct BenchView {
  std::string name;
  const BenchVolume* volume = nullptr;
  engine::CameraPose pose;
  double fovYDeg = 50.0;
};

/// Pose at `eye` looking at `targetEcef` (heading/pitch from the local ENU frame at the eye).
engine::CameraPose lookAtPose(const globe::Geodetic& eye, const glm::dvec3& targetEcef) {
  const glm::dvec3 eyeEcef = globe::geodeticToEcef(eye);
  const glm::dmat3 enu = globe::enuAxes(eye.latDeg, eye.lonDeg);
  const glm::dvec3 d = glm::normalize(targetEcef - eyeEcef);
  const double e = glm::dot(d, enu[0]), n = glm::dot(d, enu[1]), u = glm::dot(d, enu[2]);
  engine::CameraPose p;
  p.latDeg = eye.latDeg;
  p.lonDeg = eye.lonDeg;
  p.heightMeters = eye.heightMeters;
  p.headingDeg = std::atan2(e, n) * 180.0 / M_PI;
  p.pitchDeg = std::asin(std::clamp(u, -1.0, 1.0)) * 180.0 / M_PI;
  return p;
}

/// An oblique view: the camera `distanceMeters` from the site along the geodesic of
/// `bearingDeg`, `heightMeters` up, looking at the antenna.
BenchView obliqueView(const std::string& name, const BenchVolume& v, double bearingDeg, double distanceMeters,
                      double heightMeters) {
  const volume::GeolocationSite& s = v.polar.site;
  const globe::GeodesicPoint g = globe::geodesicDirect(s.latDeg, s.lonDeg, bearingDeg, distanceMeters);
  const glm::dvec3 site = globe::geodeticToEcef({s.latDeg, s.lonDeg, s.antennaHeightEllipsoidMeters});
  return {name, &v, lookAtPose({g.latDeg, g.lonDeg, heightMeters}, site), 50.0};
}

BenchView topDownView(const std::string& name, const BenchVolume& v, double heightMeters) {
  engine::CameraPose p;
  p.latDeg = v.polar.site.latDeg;
  p.lonDeg = v.polar.site.lonDeg;
  p.heightMeters = heightMeters;
  p.headingDeg = 0.0;
  p.pitchDeg = -90.0;
  return {name, &v, p, 60.0};
}

Result<BenchVolume> loadVolume(const std::string& key, const std::string& path) {
  volume::RadarLoadOptions load;
  load.buildRenderLayout = true;
  auto radar = volume::loadRadar(path, load);
  if (!radar) return radar.forwardError();
  BenchVolume v;
  v.key = key;
  v.path = path;
  v.polar = std::move(*radar->layout);
  return v;
}

// ---------------------------------------------------------------------------------------------
// Settings (grid cells)

struct Cell {
  volume::VolumeRenderMode mode = volume::VolumeRenderMode::Dvr;
  double stepMeters = 250.0;
  double imageScale = 1.0;
  volume::Interpolation interpolation = volume::Interpolation::Linear;
  engine::BeamApproximation beam = engine::BeamApproximation::EffectiveEarthLocalSphere;
  engine::Classification classification = engine::Classification::Point;
};

const char* modeName(volume::VolumeRenderMode m) {
  return m == volume::VolumeRenderMode::Dvr ? "dvr" : m == volume::VolumeRenderMode::Mip ? "mip" : "iso";
}
const char* interpName(volume::Interpolation i) { return i == volume::Interpolation::Linear ? "linear" : "nearest"; }
const char* beamName(engine::BeamApproximation b) {
  return b == engine::BeamApproximation::EffectiveEarthLocalSphere ? "4/3-earth" : "straight";
}

/// DVR: point or preintegrated; MIP and iso: "-" (classification does not apply).
const char* classificationName(const Cell& c) {
  if (c.mode != volume::VolumeRenderMode::Dvr) return "-";
  return c.classification == engine::Classification::Preintegrated ? "preintegrated" : "point";
}

/// The engine's defaults (VolumeRenderOptions / VolumeRenderSettings, the radar's beam model).
bool isEngineDefault(const Cell& c) {
  const engine::VolumeRenderOptions d;
  return c.stepMeters == d.render.stepMeters && c.imageScale == d.imageScale &&
         c.interpolation == d.render.interpolation && c.beam == engine::BeamApproximation::EffectiveEarthLocalSphere &&
         c.classification == d.classification;
}

engine::VolumeRenderOptions optionsFor(const Cell& c) {
  engine::VolumeRenderOptions o;
  o.render.mode = c.mode;
  o.render.stepMeters = c.stepMeters;
  o.render.interpolation = c.interpolation;
  o.render.transfer = volume::defaultReflectivityTransfer();
  o.imageScale = c.imageScale;
  o.classification = c.classification;
  o.skipEmptySpace = true;
  return o;
}

// ---------------------------------------------------------------------------------------------
// Reference images, cached on disk

std::string fmt(double v, int precision = 10) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", precision, v);
  return buf;
}

std::string referenceKey(const BenchView& view, int w, int h, const volume::VolumeRenderSettings& s) {
  std::ostringstream k;
  const engine::CameraPose& p = view.pose;
  k << "ref-v1|" << view.volume->path << "|" << view.volume->polar.fieldName << "|" << fmt(p.latDeg) << ","
    << fmt(p.lonDeg) << "," << fmt(p.heightMeters) << "," << fmt(p.headingDeg) << "," << fmt(p.pitchDeg) << ","
    << fmt(p.rollDeg) << "|fov " << fmt(view.fovYDeg) << "|" << w << "x" << h << "|" << modeName(s.mode) << "|"
    << interpName(s.interpolation) << "|step " << fmt(s.stepMeters) << "|iso " << fmt(s.isoValue) << "|term "
    << fmt(s.earlyTerminationAlpha) << "|tf " << s.transfer.colors.name() << "," << fmt(s.transfer.opacityZeroValue)
    << "," << fmt(s.transfer.opacityFullValue) << "," << fmt(s.transfer.maxOpacity) << ","
    << fmt(s.transfer.opacityReferenceMeters) << "|no-occlusion";
  return k.str();
}

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::optional<volume::VolumeImage> readCachedReference(const fs::path& file, const std::string& key) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::uint32_t keyLen = 0;
  in.read(reinterpret_cast<char*>(&keyLen), sizeof keyLen);
  if (!in || keyLen > 4096) return std::nullopt;
  std::string k(keyLen, '\0');
  in.read(k.data(), keyLen);
  std::int32_t wh[2] = {0, 0};
  in.read(reinterpret_cast<char*>(wh), sizeof wh);
  if (!in || k != key || wh[0] <= 0 || wh[1] <= 0 || wh[0] > 8192 || wh[1] > 8192) return std::nullopt;
  volume::VolumeImage img;
  img.widthPx = wh[0];
  img.heightPx = wh[1];
  img.rgbaPremultiplied.resize(static_cast<std::size_t>(wh[0]) * static_cast<std::size_t>(wh[1]));
  in.read(reinterpret_cast<char*>(img.rgbaPremultiplied.data()),
          static_cast<std::streamsize>(img.rgbaPremultiplied.size() * sizeof(glm::dvec4)));
  if (!in) return std::nullopt;
  return img;
}

void writeCachedReference(const fs::path& file, const std::string& key, const volume::VolumeImage& img) {
  const fs::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    const auto keyLen = static_cast<std::uint32_t>(key.size());
    out.write(reinterpret_cast<const char*>(&keyLen), sizeof keyLen);
    out.write(key.data(), static_cast<std::streamsize>(key.size()));
    const std::int32_t wh[2] = {img.widthPx, img.heightPx};
    out.write(reinterpret_cast<const char*>(wh), sizeof wh);
    out.write(reinterpret_cast<const char*>(img.rgbaPremultiplied.data()),
              static_cast<std::streamsize>(img.rgbaPremultiplied.size() * sizeof(glm::dvec4)));
    if (!out) return;  // a cache that cannot be written only costs time on the next run
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
}

struct ReferenceStore {
  fs::path dir;
  int threads = 2;
  double secondsRendering = 0.0;
  int rendered = 0, cached = 0;

  volume::VolumeImage get(const BenchView& view, int w, int h, const volume::VolumeRenderSettings& s) {
    const std::string key = referenceKey(view, w, h, s);
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.ref", static_cast<unsigned long long>(fnv1a(key)));
    const fs::path file = dir / name;
    if (auto img = readCachedReference(file, key)) {
      ++cached;
      return *img;
    }
    const engine::Camera camera(view.pose, view.fovYDeg, w, h);
    std::cout << "  reference " << view.name << " " << modeName(s.mode) << " " << w << "x" << h << " step "
              << s.stepMeters << " m ..." << std::flush;
    const auto t0 = Clock::now();
    volume::VolumeImage img =
        volume::renderReference(view.volume->polar, s, engine::referenceCameraFor(camera), false, threads);
    const double sec = std::chrono::duration<double>(Clock::now() - t0).count();
    secondsRendering += sec;
    ++rendered;
    std::cout << " " << fmt(sec, 4) << " s\n";
    writeCachedReference(file, key, img);
    return img;
  }
};

volume::VolumeRenderSettings referenceSettings(volume::VolumeRenderMode mode, double stepMeters) {
  volume::VolumeRenderSettings s;
  s.mode = mode;
  s.interpolation = volume::Interpolation::Linear;
  s.stepMeters = stepMeters;
  s.transfer = volume::defaultReflectivityTransfer();
  return s;
}

volume::VolumeImage fromRgba8(const globe::ImageRGBA8& img) {
  volume::VolumeImage out;
  out.widthPx = img.width;
  out.heightPx = img.height;
  out.rgbaPremultiplied.resize(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height));
  for (std::size_t i = 0; i < out.rgbaPremultiplied.size(); ++i) {
    const std::uint8_t* p = &img.pixels[4 * i];
    out.rgbaPremultiplied[i] = glm::dvec4(p[0], p[1], p[2], p[3]) / 255.0;
  }
  return out;
}

globe::ImageRGBA8 toRgba8(const volume::VolumeImage& img) {
  globe::ImageRGBA8 out = globe::ImageRGBA8::filled(img.widthPx, img.heightPx, {0, 0, 0, 255});
  for (int y = 0; y < img.heightPx; ++y)
    for (int x = 0; x < img.widthPx; ++x) {
      const glm::dvec3 c = glm::clamp(glm::dvec3(img.at(x, y)), 0.0, 1.0);
      out.set(x, y, glm::u8vec4(glm::round(c * 255.0), 255));
    }
  return out;
}

// ---------------------------------------------------------------------------------------------
// GPU timing

struct GpuRun {
  double medianMs = 0.0;
  globe::ImageRGBA8 image;  ///< the composited frame (what the user sees), over black
};

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Draws the volume alone over black into `target` (the globe is not drawn: empty depth, so
/// nothing occludes the volume, as in the reference with occlusion off); one warm-up frame,
/// then `frames` timed frames, each ended by glFinish. The image is the last frame's
/// composite: for imageScale < 1 that is the marcher's small image upsampled bilinearly by the
/// composite pass, exactly what a user sees.
GpuRun timeGpu(engine::VolumeRendererGL& r, const engine::Camera& camera, const BenchVolume& v,
               const engine::VolumeRenderOptions& o, engine::BeamApproximation beam, engine::FramebufferGL& target,
               int frames, bool warmUp = true) {
  v.gl->setBeamApproximation(beam);
  std::vector<double> ms;
  for (int f = warmUp ? -1 : 0; f < frames; ++f) {
    const auto t0 = Clock::now();
    target.bind();
    glClearDepth(0.0);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    r.draw(camera, *v.gl, o, target);
    glFinish();
    if (f >= 0) ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  return {median(ms), target.readColor()};
}

// ---------------------------------------------------------------------------------------------
// Results

struct Row {
  std::string view;
  std::string volume;
  Cell cell;
  int widthPx = 0, heightPx = 0;
  double medianMs = 0.0;
  volume::ImageError error;
};

struct Aggregate {
  Cell cell;
  double meanMs = 0.0;       ///< mean over views of the median frame time
  double meanAbs = 0.0;      ///< mean over views
  double maxAbs = 0.0;       ///< max over views
  double meanPsnrDb = 0.0;   ///< mean over views (finite values)
  double minPsnrDb = 0.0;
  bool pareto = false;
};

std::string cellLabel(const Cell& c) {
  std::ostringstream s;
  s << modeName(c.mode) << " step " << fmt(c.stepMeters) << " m, scale " << fmt(c.imageScale) << ", "
    << interpName(c.interpolation) << ", " << beamName(c.beam);
  if (c.classification == engine::Classification::Preintegrated) s << ", pre-integrated";
  return s.str();
}

bool sameCell(const Cell& a, const Cell& b) {
  return a.mode == b.mode && a.stepMeters == b.stepMeters && a.imageScale == b.imageScale &&
         a.interpolation == b.interpolation && a.beam == b.beam && a.classification == b.classification;
}

std::vector<Aggregate> aggregate(const std::vector<Row>& rows, const std::vector<Cell>& cells) {
  std::vector<Aggregate> out;
  for (const Cell& c : cells) {
    Aggregate a;
    a.cell = c;
    a.minPsnrDb = std::numeric_limits<double>::infinity();
    int n = 0;
    for (const Row& r : rows) {
      if (!sameCell(r.cell, c)) continue;
      a.meanMs += r.medianMs;
      a.meanAbs += r.error.meanAbs;
      a.maxAbs = std::max(a.maxAbs, r.error.maxAbs);
      a.meanPsnrDb += std::min(r.error.psnrDb, 99.0);
      a.minPsnrDb = std::min(a.minPsnrDb, r.error.psnrDb);
      ++n;
    }
    if (n == 0) continue;
    a.meanMs /= n, a.meanAbs /= n, a.meanPsnrDb /= n;
    out.push_back(a);
  }
  // Pareto front among DVR cells: no other cell is at least as fast and at least as accurate
  // (mean abs error) and strictly better in one.
  for (Aggregate& a : out) {
    if (a.cell.mode != volume::VolumeRenderMode::Dvr) continue;
    a.pareto = true;
    for (const Aggregate& b : out) {
      if (&a == &b || b.cell.mode != volume::VolumeRenderMode::Dvr) continue;
      if (b.meanMs <= a.meanMs && b.meanAbs <= a.meanAbs && (b.meanMs < a.meanMs || b.meanAbs < a.meanAbs)) {
        a.pareto = false;
        break;
      }
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The peer: Cartesian grid + VTK

struct PeerGrid {
  int nx = 0, ny = 0, nz = 0;
  double spacingMeters = 0.0;
  glm::dvec3 originEnu{0.0};      ///< centre of voxel (0,0,0), ENU at the antenna (m)
  double nativeSpacingMeters = 0.0;
  std::string coarsenedReason;
  double maxRangeErrorMeters = 0.0, maxAzimuthErrorDeg = 0.0, maxElevationErrorDeg = 0.0;
  double resampleSeconds = 0.0;
  double bytes() const { return static_cast<double>(nx) * ny * nz * sizeof(float); }
};

/// Fast inverse for resampling (ENU relative to the antenna -> antenna coordinates): the Earth
/// near the site replaced by a sphere of radius rs (the Gaussian radius of curvature at the
/// site) touching the ellipsoid below the antenna; height above it and arc distance on it,
/// then the effective-Earth beam model inverted in closed form. Its error against
/// antennaCoordinatesExact is measured in buildPeerGrid and reported.
struct FastInverse {
  double rs = 0.0, h0 = 0.0, re = 0.0;
  volume::AntennaCoordinates operator()(const glm::dvec3& enu) const {
    const glm::dvec3 q(enu.x, enu.y, enu.z + rs + h0);
    const double horiz = std::hypot(q.x, q.y);
    const double rho = std::hypot(horiz, q.z);
    const double h = rho - rs;
    const double s = rs * std::atan2(horiz, q.z);
    const double a = s / re;
    const double x = (re + h) * std::sin(a), y = (re + h) * std::cos(a) - (re + h0);
    volume::AntennaCoordinates out;
    out.rangeMeters = std::hypot(x, y);
    out.elevationDeg = std::atan2(y, x) * 180.0 / M_PI;
    double az = std::atan2(q.x, q.y) * 180.0 / M_PI;
    if (az < 0.0) az += 360.0;
    out.azimuthDeg = az;
    return out;
  }
  glm::dvec3 forward(double rangeMeters, double azDeg, double elDeg) const {
    double h = 0.0, s = 0.0;
    volume::beamHeightAndGroundDistance(rangeMeters, elDeg, h0, re, &h, &s);
    const double g = s / rs, az = azDeg * M_PI / 180.0;
    return {(rs + h) * std::sin(g) * std::sin(az), (rs + h) * std::sin(g) * std::cos(az), (rs + h) * std::cos(g) - rs - h0};
  }
};

FastInverse fastInverseFor(const volume::PolarVolume& v) {
  const double lat = v.site.latDeg * M_PI / 180.0;
  const double a = globe::kWgs84A, e2 = globe::kWgs84F * (2.0 - globe::kWgs84F);
  const double w = 1.0 - e2 * std::sin(lat) * std::sin(lat);
  const double m = a * (1.0 - e2) / std::pow(w, 1.5), n = a / std::sqrt(w);
  FastInverse f;
  f.rs = std::sqrt(m * n);
  f.h0 = v.site.antennaHeightEllipsoidMeters;
  f.re = volume::effectiveEarthRadiusMeters(v.beam, v.site.latDeg);
  return f;
}

/// Resamples `v` onto a Cartesian ENU grid at the finest gate spacing over the bounding box of
/// the gates that can be seen (value above the transfer function's zero-opacity value), coarsened
/// uniformly when a side would exceed 2048 voxels (GL_MAX_3D_TEXTURE_SIZE) or the grid
/// `maxVoxels`. Voxels get the linear sampling rule's value (samplePolar) at the fast inverse's
/// antenna coordinates; no echo / no data become `emptyValue` (zero opacity).
PeerGrid buildPeerGrid(const volume::PolarVolume& v, double emptyValue, double visibleAbove, double maxVoxels,
                       int threads, std::vector<float>* values) {
  const FastInverse inv = fastInverseFor(v);
  PeerGrid g;
  g.nativeSpacingMeters = std::numeric_limits<double>::infinity();
  for (const auto& s : v.sweeps) g.nativeSpacingMeters = std::min(g.nativeSpacingMeters, s.gateSpacingMeters);
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  const double hb = 0.5 * v.beamWidthDeg;
  for (std::size_t k = 0; k < v.sweeps.size(); ++k) {
    const auto& s = v.sweeps[k];
    for (int ray = 0; ray < s.rayCount; ++ray)
      for (int gate = 0; gate < s.gateCount; ++gate) {
        const float val = v.value(static_cast<int>(k), ray, gate);
        if (!(val > visibleAbove)) continue;
        const double r = s.firstGateRangeMeters + gate * s.gateSpacingMeters;
        for (double de : {-hb, hb}) {
          const glm::dvec3 p = inv.forward(r, s.azimuthDeg[static_cast<std::size_t>(ray)], s.elevationDeg + de);
          lo = glm::min(lo, p), hi = glm::max(hi, p);
        }
      }
  }
  if (!std::isfinite(lo.x)) return g;
  const double margin = 2.0 * g.nativeSpacingMeters;
  lo -= margin, hi += margin;
  const glm::dvec3 ext = hi - lo;
  double spacing = g.nativeSpacingMeters;
  const double maxSide = std::max({ext.x, ext.y, ext.z}) / spacing;
  const double voxels = (ext.x / spacing) * (ext.y / spacing) * (ext.z / spacing);
  const double coarsen = std::max({1.0, maxSide / 2047.0, std::cbrt(voxels / maxVoxels)});
  if (coarsen > 1.0) {
    spacing *= coarsen;
    std::ostringstream why;
    why << "native " << fmt(g.nativeSpacingMeters) << " m would be " << fmt(std::ceil(ext.x / g.nativeSpacingMeters))
        << " x " << fmt(std::ceil(ext.y / g.nativeSpacingMeters)) << " x " << fmt(std::ceil(ext.z / g.nativeSpacingMeters))
        << " voxels (" << fmt(voxels * 4.0 / 1e9, 3) << " GB float32); limits: 2048 per side "
        << "(GL_MAX_3D_TEXTURE_SIZE) and " << fmt(maxVoxels * 4.0 / 1e9, 3) << " GB";
    g.coarsenedReason = why.str();
  }
  g.spacingMeters = spacing;
  g.nx = static_cast<int>(std::ceil(ext.x / spacing)) + 1;
  g.ny = static_cast<int>(std::ceil(ext.y / spacing)) + 1;
  g.nz = static_cast<int>(std::ceil(ext.z / spacing)) + 1;
  g.originEnu = lo;

  // Error of the fast inverse against the exact one, at random voxel centres inside the range.
  {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y), uz(lo.z, hi.z);
    const glm::dmat3 enu = globe::enuAxes(v.site.latDeg, v.site.lonDeg);
    const glm::dvec3 site = globe::geodeticToEcef({v.site.latDeg, v.site.lonDeg, v.site.antennaHeightEllipsoidMeters});
    for (int i = 0; i < 20000; ++i) {
      const glm::dvec3 p(ux(rng), uy(rng), uz(rng));
      const volume::AntennaCoordinates f = inv(p);
      if (f.rangeMeters > v.maxRangeMeters || f.rangeMeters < 1e3) continue;
      const volume::AntennaCoordinates e = volume::antennaCoordinatesExact(v.site, v.beam, site + enu * p);
      g.maxRangeErrorMeters = std::max(g.maxRangeErrorMeters, std::abs(f.rangeMeters - e.rangeMeters));
      double daz = std::abs(f.azimuthDeg - e.azimuthDeg);
      daz = std::min(daz, 360.0 - daz);
      g.maxAzimuthErrorDeg = std::max(g.maxAzimuthErrorDeg, daz);
      g.maxElevationErrorDeg = std::max(g.maxElevationErrorDeg, std::abs(f.elevationDeg - e.elevationDeg));
    }
  }

  const auto t0 = Clock::now();
  values->assign(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny) * static_cast<std::size_t>(g.nz),
                 static_cast<float>(emptyValue));
  auto work = [&](int first) {
    for (int k = first; k < g.nz; k += threads) {
      for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
          const glm::dvec3 p = lo + spacing * glm::dvec3(i, j, k);
          const volume::AntennaCoordinates a = inv(p);
          if (a.rangeMeters > v.maxRangeMeters) continue;
          const volume::PolarSample s =
              volume::samplePolar(v, a.rangeMeters, a.azimuthDeg, a.elevationDeg, volume::Interpolation::Linear);
          if (s.state == volume::PolarSample::State::Echo) {
            (*values)[(static_cast<std::size_t>(k) * g.ny + static_cast<std::size_t>(j)) * g.nx +
                      static_cast<std::size_t>(i)] = static_cast<float>(s.value);
          }
        }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(work, t);
  for (auto& t : pool) t.join();
  g.resampleSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return g;
}

struct PeerResult {
  std::string view, mapper;
  double medianMs = 0.0;
  double peakRssMb = 0.0;
  volume::ImageError error;
  bool ok = false;
  std::string note;
};

std::string findPeerScript(const BenchOptions& o) {
  if (!o.peerScript.empty()) return o.peerScript;
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

// ---------------------------------------------------------------------------------------------

std::string machineLine(const std::string& gl) {
  std::string cpu;
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  std::ostringstream s;
  s << "CPU: " << cpu << ", " << std::thread::hardware_concurrency() << " hardware threads; GL: " << gl;
  return s.str();
}

int runBench(const BenchOptions& o) {
  const auto tStart = Clock::now();
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::error_code ec;
  fs::create_directories(fs::path(o.outDir) / "reference-cache", ec);
  if (ec) return fail("bench", o.outDir + ": cannot create directory: " + ec.message());

  // The volumes and their views (the quick run: KLBB oblique only); --view names are checked
  // before anything is loaded.
  std::vector<std::pair<std::string, std::string>> files = {
      {"KLBB", "radar_nexrad/KLBB20160601_150025_V06"}, {"AU40", "radar_odim/40_20181220_060630.pvol.h5"}};
  if (o.quick) files.resize(1);
  std::vector<std::string> knownViews;
  for (const auto& file : files) {
    knownViews.push_back(file.first + "-oblique");
    if (!o.quick) knownViews.push_back(file.first + "-down");
  }
  for (const std::string& name : o.viewNames) {
    if (std::find(knownViews.begin(), knownViews.end(), name) == knownViews.end()) {
      std::string known;
      for (const std::string& k : knownViews) known += (known.empty() ? "" : ", ") + k;
      return fail("bench", "--view " + name + ": no such view (views" + (o.quick ? " with --quick" : "") + ": " + known + ")");
    }
  }
  auto wanted = [&](const std::string& view) {
    return o.viewNames.empty() || std::find(o.viewNames.begin(), o.viewNames.end(), view) != o.viewNames.end();
  };

  // --reference-only: no GL at all (fills the reference cache, e.g. on a many-core machine).
  std::unique_ptr<engine::HeadlessContextGL> context;
  std::unique_ptr<engine::VolumeRendererGL> renderer;
  std::string glName = "none";
  if (!o.referenceOnly) {
    auto c = engine::HeadlessContextGL::create();
    if (!c) return fail("bench", c.error());
    context = std::move(*c);
    glName = context->describe();
    auto r = engine::VolumeRendererGL::create();
    if (!r) return fail("bench", r.error());
    renderer = std::move(*r);
  }

  // Volumes (only those a chosen view shows).
  std::vector<std::unique_ptr<BenchVolume>> volumes;
  for (const auto& [key, rel] : files) {
    if (!wanted(key + "-oblique") && !wanted(key + "-down")) continue;
    const std::string path = (fs::path(o.dataDir) / rel).string();
    auto v = loadVolume(key, path);
    if (!v) return fail("bench", v.error());
    if (!o.referenceOnly) {
      auto gl = engine::RadarVolumeGL::create(v->polar);
      if (!gl) return fail("bench", path + ": " + gl.error());
      v->gl = std::move(*gl);
    }
    volumes.push_back(std::make_unique<BenchVolume>(std::move(*v)));
    std::cout << key << ": " << path << ", field " << volumes.back()->polar.fieldName << ", "
              << volumes.back()->polar.sweeps.size() << " sweeps\n";
  }

  // Views: oblique (200 km out, 100 km up, looking at the antenna) and straight down from 400 km.
  std::vector<BenchView> views;
  for (const auto& v : volumes) {
    const double bearing = v->key == "KLBB" ? 180.0 : 225.0;
    views.push_back(obliqueView(v->key + "-oblique", *v, bearing, 200e3, 100e3));
    if (!o.quick) views.push_back(topDownView(v->key + "-down", *v, 400e3));
  }
  std::erase_if(views, [&](const BenchView& v) { return !wanted(v.name); });

  // The grid.
  const int w = o.quick ? 160 : 320, h = o.quick ? 90 : 180;
  std::vector<double> steps = {125.0, 250.0, 500.0, 750.0, 1000.0, 1500.0, 2000.0};
  std::vector<double> scales = {1.0, 0.5, 0.25};
  if (o.quick) steps = {250.0, 1000.0}, scales = {1.0, 0.5};
  if (!o.stepsMeters.empty()) {
    steps = o.stepsMeters;
    std::sort(steps.begin(), steps.end());
    steps.erase(std::unique(steps.begin(), steps.end()), steps.end());
  }
  std::vector<Cell> cells;
  for (double step : steps)
    for (double scale : scales)
      for (auto interp : {volume::Interpolation::Nearest, volume::Interpolation::Linear})
        for (auto beam : {engine::BeamApproximation::EffectiveEarthLocalSphere, engine::BeamApproximation::StraightLine}) {
          Cell c;
          c.stepMeters = step, c.imageScale = scale, c.interpolation = interp, c.beam = beam;
          cells.push_back(c);
          // Pre-integration assumes the field linear between samples: with linear interpolation only.
          if (interp == volume::Interpolation::Linear) {
            c.classification = engine::Classification::Preintegrated;
            cells.push_back(c);
          }
        }
  for (auto mode : {volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
    Cell c;
    c.mode = mode;
    cells.push_back(c);
  }

  ReferenceStore refs;
  refs.dir = fs::path(o.outDir) / "reference-cache";
  refs.threads = threads;

  if (o.referenceOnly) {
    for (const BenchView& view : views) {
      for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso})
        refs.get(view, w, h, referenceSettings(mode, o.referenceStepMeters));
      if (!o.quick) {
        refs.get(view, 80, 45, referenceSettings(volume::VolumeRenderMode::Dvr, o.referenceStepMeters));
        refs.get(view, 80, 45, referenceSettings(volume::VolumeRenderMode::Dvr, o.referenceStepMeters / 2.0));
      }
    }
    std::cout << "references: " << refs.rendered << " rendered (" << refs.secondsRendering << " s), " << refs.cached
              << " cached, in " << refs.dir.string() << "\n";
    return 0;
  }
  auto target = engine::FramebufferGL::create(w, h);
  if (!target) return fail("bench", target.error());
  std::vector<Row> rows;
  for (const BenchView& view : views) {
    std::cout << "view " << view.name << " (" << w << "x" << h << ")\n";
    const engine::Camera camera(view.pose, view.fovYDeg, w, h);
    std::map<volume::VolumeRenderMode, volume::VolumeImage> ref;
    for (auto mode : {volume::VolumeRenderMode::Dvr, volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
      ref[mode] = refs.get(view, w, h, referenceSettings(mode, o.referenceStepMeters));
      if (auto s = globe::writePng((fs::path(o.outDir) / (view.name + "-reference-" + modeName(mode) + ".png")).string(),
                                   toRgba8(ref[mode]));
          !s) {
        return fail("bench", s.error());
      }
    }
    // Frames round-robin over the cells (frame 1 of every cell, then frame 2, ...), one untimed
    // round first: a slow spell of the shared machine then lands on every cell alike instead of
    // on whichever cells it happened to overlap (in per-cell runs one cell's median came out 2x
    // its neighbours' now and then). The image compared is each cell's last frame.
    std::vector<std::vector<double>> frameMs(cells.size());
    std::vector<globe::ImageRGBA8> images(cells.size());
    for (int f = -1; f < o.frames; ++f) {
      for (std::size_t ci = 0; ci < cells.size(); ++ci) {
        GpuRun run = timeGpu(*renderer, camera, *view.volume, optionsFor(cells[ci]), cells[ci].beam, **target, 1, false);
        if (f >= 0) frameMs[ci].push_back(run.medianMs);
        if (f + 1 == o.frames) images[ci] = std::move(run.image);
      }
    }
    for (std::size_t ci = 0; ci < cells.size(); ++ci) {
      const Cell& c = cells[ci];
      Row r;
      r.view = view.name;
      r.volume = view.volume->key;
      r.cell = c;
      r.widthPx = w, r.heightPx = h;
      r.medianMs = median(frameMs[ci]);
      r.error = volume::compareImages(fromRgba8(images[ci]), ref[c.mode]);
      rows.push_back(r);
      if (isEngineDefault(c)) {
        if (auto s = globe::writePng((fs::path(o.outDir) / (view.name + "-gpu-" + modeName(c.mode) + ".png")).string(),
                                     images[ci]);
            !s) {
          return fail("bench", s.error());
        }
      }
    }
  }

  // The default at 1280x720 (time only: a reference at that size would take ~15x longer).
  struct BigTiming {
    std::string view;
    double ms;
  };
  std::vector<BigTiming> big;
  {
    auto bigTarget = engine::FramebufferGL::create(1280, 720);
    if (!bigTarget) return fail("bench", bigTarget.error());
    // On a software rasteriser (llvmpipe) one 1280x720 frame takes minutes: time the first view
    // only, with one frame.
    const bool software = glName.find("llvmpipe") != std::string::npos || glName.find("softpipe") != std::string::npos;
    for (const BenchView& view : views) {
      const engine::Camera camera(view.pose, view.fovYDeg, 1280, 720);
      big.push_back({view.name + (software ? " (1 frame, software GL)" : ""),
                     timeGpu(*renderer, camera, *view.volume, optionsFor(Cell{}), Cell{}.beam, **bigTarget, software ? 1 : o.frames, !software).medianMs});
      if (software) break;
    }
  }

  // Reference convergence: the reference step against half of it, on a small image.
  struct Convergence {
    std::string view;
    volume::ImageError error;
  };
  std::vector<Convergence> convergence;
  for (const BenchView& view : views) {
    if (o.quick) break;
    const int cw = 80, ch = 45;
    const volume::VolumeImage a = refs.get(view, cw, ch, referenceSettings(volume::VolumeRenderMode::Dvr, o.referenceStepMeters));
    const volume::VolumeImage b =
        refs.get(view, cw, ch, referenceSettings(volume::VolumeRenderMode::Dvr, o.referenceStepMeters / 2.0));
    convergence.push_back({view.name, volume::compareImages(a, b)});
  }

  const std::vector<Aggregate> agg = aggregate(rows, cells);

  // CSV.
  {
    std::ofstream csv(fs::path(o.outDir) / "volume_bench.csv");
    csv << "view,volume,mode,step_m,image_scale,interpolation,beam,classification,width_px,height_px,median_ms,mean_abs,"
           "max_abs,psnr_db,engine_default\n";
    for (const Row& r : rows) {
      csv << r.view << "," << r.volume << "," << modeName(r.cell.mode) << "," << r.cell.stepMeters << ","
          << r.cell.imageScale << "," << interpName(r.cell.interpolation) << "," << beamName(r.cell.beam) << ","
          << classificationName(r.cell) << ","
          << r.widthPx << "," << r.heightPx << "," << fmt(r.medianMs, 5) << "," << fmt(r.error.meanAbs, 5) << ","
          << fmt(r.error.maxAbs, 5) << "," << fmt(r.error.psnrDb, 5) << "," << (isEngineDefault(r.cell) ? 1 : 0)
          << "\n";
    }
  }

  // Plot.
  {
    engine::ScatterPlot plot;
    plot.title = "Radar volume marcher: error vs frame time (" + std::to_string(w) + "x" + std::to_string(h) +
                 ", mean of " + std::to_string(views.size()) + " views)";
    plot.xLabel = "median frame time (ms, log)";
    plot.yLabel = "mean abs error vs reference (8-bit steps)";
    plot.logX = true;
    const glm::u8vec4 colors[6] = {{31, 119, 180, 255}, {255, 127, 14, 255}, {44, 160, 44, 255},
                                   {214, 39, 40, 255},  {148, 103, 189, 255}, {140, 86, 75, 255}};
    std::vector<const Aggregate*> front;
    for (const Aggregate& a : agg) {
      if (a.cell.mode != volume::VolumeRenderMode::Dvr) continue;
      const int ci = (a.cell.classification == engine::Classification::Preintegrated ? 4
                      : a.cell.interpolation == volume::Interpolation::Linear ? 0
                                                                                 : 2) +
                     (a.cell.beam == engine::BeamApproximation::EffectiveEarthLocalSphere ? 0 : 1);
      engine::PlotPoint p;
      p.x = a.meanMs, p.y = a.meanAbs, p.color = colors[ci];
      p.radiusPx = a.cell.imageScale == 1.0 ? 5 : a.cell.imageScale == 0.5 ? 4 : 3;
      if (isEngineDefault(a.cell)) {
        p.ring = true;
        p.label = "default";
      }
      if (a.pareto) front.push_back(&a);
      plot.points.push_back(p);
    }
    std::sort(front.begin(), front.end(), [](const Aggregate* a, const Aggregate* b) { return a->meanMs < b->meanMs; });
    engine::PlotLine line;
    line.color = {120, 120, 120, 255};
    for (const Aggregate* a : front) line.points.push_back({a->meanMs, a->meanAbs});
    plot.lines.push_back(line);
    plot.legend = {{"linear, 4/3 Earth", colors[0]},
                   {"linear, straight", colors[1]},
                   {"nearest, 4/3 Earth", colors[2]},
                   {"nearest, straight", colors[3]},
                   {"linear, 4/3 Earth, pre-integrated", colors[4]},
                   {"linear, straight, pre-integrated", colors[5]},
                   {"grey line: Pareto front", {120, 120, 120, 255}},
                   {"disc size: image scale 1/.5/.25", {0, 0, 0, 255}}};
    if (auto s = globe::writePng((fs::path(o.outDir) / "volume_bench.png").string(), engine::drawScatterPlot(plot, 960, 600));
        !s) {
      return fail("bench", s.error());
    }
  }

  // Peer.
  std::vector<PeerResult> peer;
  std::string peerNote;
  std::map<std::string, PeerGrid> peerGrids;
  const std::string script = findPeerScript(o);
  const bool haveVtk = std::system("/usr/bin/python3 -c 'import vtk' >/dev/null 2>&1") == 0;
  const bool haveXvfb = std::system("command -v xvfb-run >/dev/null 2>&1") == 0;
  if (!o.peer) {
    peerNote = "peer skipped (--no-peer)";
  } else if (!haveVtk || !haveXvfb || script.empty()) {
    peerNote = std::string("peer skipped: ") + (!haveVtk ? "python3-vtk9 is not installed" : !haveXvfb ? "xvfb-run is missing" : "tools/bench/vtk_peer.py not found") +
               " (install with: sudo apt-get install python3-vtk9 xvfb)";
  } else {
    for (const auto& v : volumes) {
      const auto transfer = volume::defaultReflectivityTransfer();
      std::vector<float> grid;
      std::cout << "peer: resampling " << v->key << " to a Cartesian grid ..." << std::flush;
      const double maxVoxels = o.quick ? 3.2e7 : 2.7e8;
      PeerGrid g = buildPeerGrid(v->polar, transfer.opacityZeroValue, transfer.opacityZeroValue, maxVoxels, threads, &grid);
      if (g.nx == 0) continue;
      std::cout << " " << g.nx << "x" << g.ny << "x" << g.nz << " at " << g.spacingMeters << " m, "
                << fmt(g.resampleSeconds, 3) << " s\n";
      const fs::path dir = fs::path(o.outDir) / "peer";
      fs::create_directories(dir, ec);
      const fs::path raw = dir / (v->key + "-grid.f32");
      {
        std::ofstream out(raw, std::ios::binary);
        out.write(reinterpret_cast<const char*>(grid.data()), static_cast<std::streamsize>(grid.size() * sizeof(float)));
        if (!out) return fail("bench", raw.string() + ": cannot write the peer grid");
      }
      grid.clear();
      grid.shrink_to_fit();
      nlohmann::json job;
      job["grid"] = {{"file", fs::absolute(raw).string()}, {"dims", {g.nx, g.ny, g.nz}}, {"spacing_m", g.spacingMeters},
                     {"origin_enu_m", {g.originEnu.x, g.originEnu.y, g.originEnu.z}}};
      job["transfer"] = transferJson(transfer);
      job["frames"] = o.frames;
      job["sample_distance_m"] = g.spacingMeters;
      job["out_dir"] = fs::absolute(dir).string();
      const glm::dmat3 enu = globe::enuAxes(v->polar.site.latDeg, v->polar.site.lonDeg);
      const glm::dvec3 site = globe::geodeticToEcef(
          {v->polar.site.latDeg, v->polar.site.lonDeg, v->polar.site.antennaHeightEllipsoidMeters});
      nlohmann::json jviews = nlohmann::json::array();
      for (const BenchView& view : views) {
        if (view.volume != v.get()) continue;
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
      const fs::path jobFile = dir / (v->key + "-job.json");
      std::ofstream(jobFile) << job.dump(2);
      const fs::path resultFile = dir / (v->key + "-result.json");
      fs::remove(resultFile, ec);
      const std::string cmd = "xvfb-run -a -s '-screen 0 1280x1024x24' /usr/bin/python3 '" + script + "' '" +
                              fs::absolute(jobFile).string() + "' '" + fs::absolute(resultFile).string() + "'";
      std::cout << "peer: " << cmd << "\n";
      const int rc = std::system(cmd.c_str());
      peerGrids[v->key] = g;
      std::ifstream rin(resultFile);
      if (rc != 0) {
        // The script rewrites its result after every mapper and view, so what finished before
        // a crash (VTK aborts the process, e.g. on a lost X connection) is still reported.
        peerNote += "VTK peer for " + v->key + " failed (exit " + std::to_string(rc) + ")" +
                    (rin ? "; the runs that finished before are below" : "") + "; ";
      }
      if (!rin) continue;
      nlohmann::json res;
      try {
        rin >> res;
      } catch (const std::exception& e) {
        peerNote += resultFile.string() + ": " + e.what() + "; ";
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
              refs.get(*view, w, h, referenceSettings(volume::VolumeRenderMode::Dvr, o.referenceStepMeters));
          pr.error = volume::compareImages(fromRgba8(*img), ref);
          pr.ok = true;
        } else {
          pr.note += " (no image)";
        }
        peer.push_back(pr);
      }
    }
  }

  // Markdown.
  {
    std::ofstream md(fs::path(o.outDir) / "volume_bench.md");
    md << "# atmoglobe bench: radar volume marcher\n\n";
    md << "Machine: " << machineLine(glName) << "\n\n";
    md << "Image " << w << "x" << h << " px, " << o.frames << " timed frames per cell (median, glFinish after each, "
       << "frames taken round-robin over the cells after one untimed round), volume only over black (no globe). Error against the CPU reference (double, exact "
       << "inverse, linear, step " << fmt(o.referenceStepMeters) << " m, full resolution, no empty-space skipping; only samples proven outside the shell skip the inverse, bit-identical): "
       << "mean / max absolute difference in 8-bit steps over RGB, PSNR in dB. For image scale < 1 the frame is the "
       << "small image upsampled bilinearly by the composite pass (what the user sees).\n\n";
    md << "## Volumes\n\n| volume | file | field | sweeps | GPU bytes | Cartesian grid at near-range resolution (float32) | ratio |\n|---|---|---|---|---|---|---|\n";
    for (const auto& v : volumes) {
      const double cart = volume::cartesianEquivalentBytes(v->polar, 4.0);
      md << "| " << v->key << " | " << v->path << " | " << v->polar.fieldName << " | " << v->polar.sweeps.size()
         << " | " << fmt(static_cast<double>(v->gl->gpuBytes()) / 1e6, 4) << " MB | " << fmt(cart / 1e9, 4) << " GB | "
         << fmt(cart / static_cast<double>(v->gl->gpuBytes()), 4) << "x |\n";
    }
    md << "\n## Views\n\n| view | lat | lon | height (m) | heading | pitch | fovY |\n|---|---|---|---|---|---|---|\n";
    for (const BenchView& v : views) {
      md << "| " << v.name << " | " << fmt(v.pose.latDeg, 7) << " | " << fmt(v.pose.lonDeg, 7) << " | "
         << fmt(v.pose.heightMeters) << " | " << fmt(v.pose.headingDeg, 4) << " | " << fmt(v.pose.pitchDeg, 4) << " | "
         << fmt(v.fovYDeg) << " |\n";
    }
    md << "\nReferences: " << refs.rendered << " rendered this run (" << fmt(refs.secondsRendering, 4) << " s on "
       << threads << " threads), " << refs.cached << " read from the cache (" << refs.dir.string() << ").\n";
    if (!convergence.empty()) {
      md << "\nReference convergence (DVR, 80x45, step " << fmt(o.referenceStepMeters) << " m against "
         << fmt(o.referenceStepMeters / 2) << " m):\n\n| view | mean abs | max abs | PSNR dB |\n|---|---|---|---|\n";
      for (const auto& c : convergence)
        md << "| " << c.view << " | " << fmt(c.error.meanAbs, 3) << " | " << fmt(c.error.maxAbs, 3) << " | "
           << fmt(c.error.psnrDb, 3) << " |\n";
    }
    md << "\n## All settings, mean over views (sorted by time)\n\n"
       << "| mode | step (m) | scale | interp. | beam | classification | frame (ms) | mean abs | max abs | PSNR mean (dB) | PSNR min (dB) | Pareto | default |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::vector<Aggregate> sorted = agg;
    std::sort(sorted.begin(), sorted.end(), [](const Aggregate& a, const Aggregate& b) { return a.meanMs < b.meanMs; });
    for (const Aggregate& a : sorted) {
      md << "| " << modeName(a.cell.mode) << " | " << fmt(a.cell.stepMeters) << " | " << fmt(a.cell.imageScale) << " | "
         << interpName(a.cell.interpolation) << " | " << beamName(a.cell.beam) << " | "
         << classificationName(a.cell) << " | "
         << fmt(a.meanMs, 4) << " | "
         << fmt(a.meanAbs, 3) << " | " << fmt(a.maxAbs, 3) << " | " << fmt(a.meanPsnrDb, 3) << " | "
         << fmt(a.minPsnrDb, 3) << " | " << (a.pareto ? "yes" : "") << " | " << (isEngineDefault(a.cell) ? "**yes**" : "")
         << " |\n";
    }
    md << "\n## Per view\n\n| view | setting | frame (ms) | mean abs | max abs | PSNR (dB) |\n|---|---|---|---|---|---|\n";
    for (const Row& r : rows)
      md << "| " << r.view << " | " << cellLabel(r.cell) << (isEngineDefault(r.cell) ? " (default)" : "") << " | "
         << fmt(r.medianMs, 4) << " | " << fmt(r.error.meanAbs, 3) << " | " << fmt(r.error.maxAbs, 3) << " | "
         << fmt(r.error.psnrDb, 3) << " |\n";
    md << "\n## Default setting at 1280x720 (time only)\n\n| view | frame (ms) |\n|---|---|\n";
    for (const auto& b : big) md << "| " << b.view << " | " << fmt(b.ms, 4) << " |\n";
    md << "\n## Peer: Cartesian grid rendered by VTK\n\n";
    if (!peerNote.empty()) md << peerNote << "\n\n";
    for (const auto& [key, g] : peerGrids) {
      const BenchVolume* v = nullptr;
      for (const auto& bv : volumes)
        if (bv->key == key) v = bv.get();
      md << "- " << key << ": grid " << g.nx << " x " << g.ny << " x " << g.nz << " at " << fmt(g.spacingMeters, 4)
         << " m (finest gate spacing " << fmt(g.nativeSpacingMeters) << " m), box = ENU bounding box of the gates above "
         << "the zero-opacity value, float32: " << fmt(g.bytes() / 1e6, 5) << " MB vs our GPU " << fmt(static_cast<double>(v->gl->gpuBytes()) / 1e6, 4)
         << " MB (" << fmt(g.bytes() / static_cast<double>(v->gl->gpuBytes()), 3) << "x). "
         << (g.coarsenedReason.empty() ? "" : "Coarsened: " + g.coarsenedReason + ". ") << "Resampled in "
         << fmt(g.resampleSeconds, 3) << " s with the fast inverse (local sphere + closed-form beam model), max error "
         << "vs the exact inverse over 20000 random voxels: " << fmt(g.maxRangeErrorMeters, 3) << " m range, "
         << fmt(g.maxAzimuthErrorDeg, 3) << " deg azimuth, " << fmt(g.maxElevationErrorDeg, 3) << " deg elevation.\n";
    }
    if (!peer.empty()) {
      md << "\n| view | renderer | frame (ms) | mean abs | max abs | PSNR (dB) | note |\n|---|---|---|---|---|---|---|\n";
      for (const PeerResult& p : peer) {
        md << "| " << p.view << " | VTK " << p.mapper << " | " << fmt(p.medianMs, 4) << " | "
           << (p.ok ? fmt(p.error.meanAbs, 3) : "-") << " | " << (p.ok ? fmt(p.error.maxAbs, 3) : "-") << " | "
           << (p.ok ? fmt(p.error.psnrDb, 3) : "-") << " | " << p.note << " |\n";
      }
      md << "\nOurs at the default on the same views:\n\n| view | frame (ms) | mean abs | max abs | PSNR (dB) |\n|---|---|---|---|---|\n";
      for (const Row& r : rows)
        if (isEngineDefault(r.cell) && r.cell.mode == volume::VolumeRenderMode::Dvr)
          md << "| " << r.view << " | " << fmt(r.medianMs, 4) << " | " << fmt(r.error.meanAbs, 3) << " | "
             << fmt(r.error.maxAbs, 3) << " | " << fmt(r.error.psnrDb, 3) << " |\n";
      if (!peer.empty()) md << "\nVTK process peak resident memory: " << fmt(peer.front().peakRssMb, 4) << " MB.\n";
    }
    md << "\nTotal bench time: " << fmt(std::chrono::duration<double>(Clock::now() - tStart).count(), 4) << " s.\n";
  }
  std::cout << (fs::path(o.outDir) / "volume_bench.md").string() << "\n"
            << (fs::path(o.outDir) / "volume_bench.csv").string() << "\n"
            << (fs::path(o.outDir) / "volume_bench.png").string() << "\n";
  if (!peerNote.empty()) std::cout << peerNote << "\n";
  return 0;
}

}  // namespace

Command addBenchCommand(CLI::App& root) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* c = root.add_subcommand("bench", "Measure the radar volume marcher's speed/accuracy trade (and the VTK peer)");
  c->add_option("--data", o->dataDir, "Directory holding radar_nexrad/ and radar_odim/ (default ../shared/data)");
  c->add_option("--out", o->outDir, "Output directory (default out/bench)");
  c->add_flag("--quick", o->quick, "One view, a small grid, 160x90 (a smoke test)");
  c->add_option("--frames", o->frames, "Timed frames per cell (median)")->check(CLI::Range(1, 1000));
  c->add_option("--reference-step", o->referenceStepMeters, "Reference renderer step (m)")->check(CLI::Range(10.0, 1000.0));
  c->add_option("--threads", o->threads, "Threads for the reference and the resampling (0: all)")->check(CLI::Range(0, 256));
  c->add_flag("!--no-peer", o->peer, "Skip the VTK peer");
  c->add_flag("--reference-only", o->referenceOnly, "Only render the reference images into the cache (no GL)");
  c->add_option("--peer-script", o->peerScript, "Path of tools/bench/vtk_peer.py");
  c->add_option("--view", o->viewNames, "Only this view (repeatable): KLBB-oblique, KLBB-down, AU40-oblique, AU40-down");
  c->add_option("--steps", o->stepsMeters, "Only these DVR step sizes (m), e.g. --steps 250 1000")
      ->check(CLI::Range(10.0, 20000.0));
  return {c, [o] { return runBench(*o); }};
}

}  // namespace atmoglobe::tools
