// CPU reference renderer (ReferenceRenderer.h): double precision, exact inverse geolocation.
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <thread>

namespace atmoglobe::volume {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

struct Span {
  double tEnter = 0.0;
  double tExit = -1.0;  // empty when tExit < tEnter
};

// The ray's intersection with the sphere |p - centre| <= radius (unit dir).
Span intersectSphere(const glm::dvec3& origin, const glm::dvec3& dir, const glm::dvec3& centre, double radius) {
  const glm::dvec3 oc = origin - centre;
  const double b = glm::dot(oc, dir);
  // |oc|^2 - b^2 is the squared distance of the centre from the ray's line: computed as the
  // length of the perpendicular part, which does not cancel when the eye is far away.
  const glm::dvec3 perp = oc - b * dir;
  const double disc = radius * radius - glm::dot(perp, perp);
  if (disc < 0.0) return {};
  const double h = std::sqrt(disc);
  return {-b - h, -b + h};
}

// Shell pre-rejection (an acceleration only: it must not change a pixel, ReferenceRendererTest
// checks bit-identical images). A point's beam elevation el (any beam model with ke > 0) and
// the straight-line elevation elS of the antenna-to-point chord in the site's ENU frame differ
// by the beam's bending against a straight line, at most r / (2 R) |1 - 1/ke| rad at chord
// length r, plus the ellipsoid-vs-sphere difference of the model (the normal-section radius in
// any azimuth is within 1 % of R: <= 0.02 deg at 460 km). With a margin of 0.25 deg on top, a
// point with elS outside [e_0 - hb - bend - margin, e_top + hb + bend + margin] is NoData
// under samplePolar and the exact inverse (~2 us) can be skipped. Points within 1 km of the
// antenna are never rejected (elS is ill-conditioned there).
struct ShellBand {
  bool enabled = false;
  glm::dvec3 upEcef{0.0};       ///< ellipsoid normal at the site
  double loDeg = 0.0, hiDeg = 0.0;
  double bendDegPerMeter = 0.0;
  static constexpr double kMarginDeg = 0.25;
  static constexpr double kMinRangeMeters = 1000.0;
};

struct Context {
  const PolarVolume& volume;
  const VolumeRenderSettings& settings;
  glm::dvec3 antennaEcef;
  ShellBand band;
};

ShellBand shellBandOf(const PolarVolume& v, bool enabled) {
  ShellBand b;
  b.enabled = enabled && !v.sweeps.empty() && v.beam.ke > 0.0;
  if (!b.enabled) return b;
  b.upEcef = globe::enuAxes(v.site.latDeg, v.site.lonDeg)[2];
  const double hb = 0.5 * v.beamWidthDeg;
  b.loDeg = v.sweeps.front().elevationDeg - hb;
  b.hiDeg = v.sweeps.back().elevationDeg + hb;
  const double radius = v.beam.earthRadiusMeters.value_or(globe::geocentricRadiusMeters(v.site.latDeg));
  b.bendDegPerMeter = std::abs(1.0 - 1.0 / v.beam.ke) / (2.0 * radius) / kDegToRad;
  return b;
}

bool provablyOutsideShell(const Context& ctx, const glm::dvec3& ecef) {
  const ShellBand& b = ctx.band;
  if (!b.enabled) return false;
  const glm::dvec3 d = ecef - ctx.antennaEcef;
  const double r = glm::length(d);
  if (!(r > ShellBand::kMinRangeMeters)) return false;
  const double elS = std::asin(std::clamp(glm::dot(d, b.upEcef) / r, -1.0, 1.0)) / kDegToRad;
  const double slack = r * b.bendDegPerMeter + ShellBand::kMarginDeg;
  return elS > b.hiDeg + slack || elS < b.loDeg - slack;
}

PolarSample sampleAt(const Context& ctx, const glm::dvec3& ecef) {
  if (provablyOutsideShell(ctx, ecef)) return PolarSample{};  // NoData
  const AntennaCoordinates ac = antennaCoordinatesExact(ctx.volume.site, ctx.volume.beam, ecef);
  return samplePolar(ctx.volume, ac.rangeMeters, ac.azimuthDeg, ac.elevationDeg, ctx.settings.interpolation);
}

// The scalar field for the ISO gradient: Echo value, else opacityZeroValue.
double fieldForGradient(const Context& ctx, const glm::dvec3& ecef) {
  const PolarSample s = sampleAt(ctx, ecef);
  return s.state == PolarSample::State::Echo ? s.value : ctx.settings.transfer.opacityZeroValue;
}

bool isoPredicate(const Context& ctx, const glm::dvec3& ecef) {
  const PolarSample s = sampleAt(ctx, ecef);
  return s.state == PolarSample::State::Echo && s.value >= ctx.settings.isoValue;
}

glm::dvec4 shadeIso(const Context& ctx, const glm::dvec3& eye, const glm::dvec3& dir, double tHit) {
  const double step = ctx.settings.stepMeters;
  double lo = tHit - step, hi = tHit;
  for (int k = 0; k < 8; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (isoPredicate(ctx, eye + mid * dir)) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  const glm::dvec3 p = eye + (0.5 * (lo + hi)) * dir;
  const double d = 0.5 * step;
  glm::dvec3 grad(0.0);
  for (int axis = 0; axis < 3; ++axis) {
    glm::dvec3 e(0.0);
    e[axis] = d;
    grad[axis] = (fieldForGradient(ctx, p + e) - fieldForGradient(ctx, p - e)) / (2.0 * d);
  }
  const double len = glm::length(grad);
  const double shade = len > 0.0 ? 0.3 + 0.7 * std::abs(glm::dot(-grad / len, dir)) : 1.0;
  const glm::dvec4 c = ctx.settings.transfer.classify(ctx.settings.isoValue);
  return glm::dvec4(glm::dvec3(c) * shade, 1.0);
}

glm::dvec4 marchRay(const Context& ctx, const glm::dvec3& eye, const glm::dvec3& dir, bool occlude) {
  const VolumeRenderSettings& st = ctx.settings;
  const double step = st.stepMeters;
  const Span span = intersectSphere(eye, dir, ctx.antennaEcef, ctx.volume.clipRadiusMeters);
  if (span.tExit < span.tEnter || span.tExit < 0.0) return glm::dvec4(0.0);
  double tLimit = std::numeric_limits<double>::infinity();
  if (occlude) {
    if (const std::optional<glm::dvec3> hit = globe::intersectRayEllipsoid(eye, dir))
      tLimit = glm::dot(*hit - eye, dir);
  }
  // i with tEnter <= (i + 0.5) step <= tExit, i >= 0.
  const double iFirst = std::max(0.0, std::ceil(span.tEnter / step - 0.5));
  const double iLast = std::floor(span.tExit / step - 0.5);

  glm::dvec4 acc(0.0);  // DVR: premultiplied rgb, alpha
  double maxValue = -std::numeric_limits<double>::infinity();
  bool anyEcho = false;
  for (double i = iFirst; i <= iLast; i += 1.0) {
    const double t = (i + 0.5) * step;
    if (!(t < tLimit)) break;
    const PolarSample s = sampleAt(ctx, eye + t * dir);
    if (s.state != PolarSample::State::Echo) continue;
    switch (st.mode) {
      case VolumeRenderMode::Dvr: {
        const glm::dvec4 c = st.transfer.classify(s.value);
        if (c.a <= 0.0) break;
        const double as = st.transfer.correctedOpacity(c.a, step);
        const double w = (1.0 - acc.a) * as;
        acc += glm::dvec4(glm::dvec3(c) * w, w);
        if (acc.a >= st.earlyTerminationAlpha) return acc;
        break;
      }
      case VolumeRenderMode::Mip:
        anyEcho = true;
        maxValue = std::max(maxValue, s.value);
        break;
      case VolumeRenderMode::Iso:
        if (s.value >= st.isoValue) return shadeIso(ctx, eye, dir, t);
        break;
    }
  }
  if (st.mode == VolumeRenderMode::Mip) {
    if (!anyEcho) return glm::dvec4(0.0);
    const glm::dvec4 c = st.transfer.classify(maxValue);
    return glm::dvec4(glm::dvec3(c) * c.a, c.a);
  }
  return st.mode == VolumeRenderMode::Dvr ? acc : glm::dvec4(0.0);
}

glm::dvec3 antennaEcefOf(const PolarVolume& v) {
  return globe::geodeticToEcef(globe::Geodetic{v.site.latDeg, v.site.lonDeg, v.site.antennaHeightEllipsoidMeters});
}

}  // namespace

RenderCamera makeLookAtCamera(const glm::dvec3& eyeEcef, const glm::dvec3& targetEcef, const glm::dvec3& upHintEcef,
                              double fovYDeg, int widthPx, int heightPx) {
  assert(fovYDeg > 0.0 && fovYDeg < 180.0 && widthPx >= 1 && heightPx >= 1);
  const glm::dvec3 forward = glm::normalize(targetEcef - eyeEcef);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, upHintEcef));
  const glm::dvec3 up = glm::cross(right, forward);
  RenderCamera cam;
  cam.eyeEcef = eyeEcef;
  cam.cameraToEcef = glm::dmat3(right, up, -forward);
  cam.focalLengthPx = heightPx / (2.0 * std::tan(0.5 * fovYDeg * kDegToRad));
  cam.widthPx = widthPx;
  cam.heightPx = heightPx;
  return cam;
}

glm::dvec3 pixelRayDirection(const RenderCamera& camera, double xPx, double yPx) {
  const double f = camera.focalLengthPx;
  const glm::dvec3 e((xPx - 0.5 * camera.widthPx) / f, (0.5 * camera.heightPx - yPx) / f, -1.0);
  return glm::normalize(camera.cameraToEcef * e);
}

std::optional<glm::dvec2> projectToPixel(const RenderCamera& camera, const glm::dvec3& ecef) {
  const glm::dvec3 e = glm::transpose(camera.cameraToEcef) * (ecef - camera.eyeEcef);
  if (e.z >= 0.0) return std::nullopt;
  const double f = camera.focalLengthPx;
  return glm::dvec2(0.5 * camera.widthPx + f * (e.x / -e.z), 0.5 * camera.heightPx - f * (e.y / -e.z));
}

glm::dvec4 renderReferenceRay(const PolarVolume& volume, const VolumeRenderSettings& settings,
                              const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef, bool occludeByEllipsoid) {
  assert(!volume.sweeps.empty() && settings.stepMeters > 0.0);
  const Context ctx{volume, settings, antennaEcefOf(volume), shellBandOf(volume, true)};
  return marchRay(ctx, eyeEcef, unitDirEcef, occludeByEllipsoid);
}

VolumeImage renderReference(const PolarVolume& volume, const VolumeRenderSettings& settings,
                            const RenderCamera& camera, bool occludeByEllipsoid, int threads, bool rejectOutsideShell) {
  assert(!volume.sweeps.empty() && settings.stepMeters > 0.0 && camera.widthPx >= 1 && camera.heightPx >= 1);
  VolumeImage img;
  img.widthPx = camera.widthPx;
  img.heightPx = camera.heightPx;
  img.rgbaPremultiplied.assign(static_cast<std::size_t>(camera.widthPx) * static_cast<std::size_t>(camera.heightPx),
                               glm::dvec4(0.0));
  const Context ctx{volume, settings, antennaEcefOf(volume), shellBandOf(volume, rejectOutsideShell)};
  const int nThreads = std::clamp(threads, 1, camera.heightPx);
  auto work = [&](int first) {
    for (int y = first; y < camera.heightPx; y += nThreads)
      for (int x = 0; x < camera.widthPx; ++x) {
        const glm::dvec3 dir = pixelRayDirection(camera, x + 0.5, y + 0.5);
        img.rgbaPremultiplied[static_cast<std::size_t>(y) * static_cast<std::size_t>(camera.widthPx) +
                              static_cast<std::size_t>(x)] = marchRay(ctx, camera.eyeEcef, dir, occludeByEllipsoid);
      }
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < nThreads; ++k) pool.emplace_back(work, k);
  work(0);
  for (std::thread& t : pool) t.join();
  return img;
}

ImageError compareImages(const VolumeImage& a, const VolumeImage& b) {
  assert(a.widthPx == b.widthPx && a.heightPx == b.heightPx);
  assert(a.rgbaPremultiplied.size() == b.rgbaPremultiplied.size());
  auto q = [](double c) { return std::round(255.0 * std::clamp(std::isfinite(c) ? c : 0.0, 0.0, 1.0)); };
  double sumAbs = 0.0, sumSq = 0.0, maxAbs = 0.0;
  const std::size_t n = a.rgbaPremultiplied.size();
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = std::abs(q(a.rgbaPremultiplied[i][c]) - q(b.rgbaPremultiplied[i][c]));
      sumAbs += d;
      sumSq += d * d;
      maxAbs = std::max(maxAbs, d);
    }
  ImageError e;
  const double count = 3.0 * static_cast<double>(n);
  e.meanAbs = n ? sumAbs / count : 0.0;
  e.maxAbs = maxAbs;
  const double mse = n ? sumSq / count : 0.0;
  e.psnrDb = mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
  return e;
}

}  // namespace atmoglobe::volume
