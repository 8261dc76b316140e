#include <atmoglobe/bench/PeerGrid.h>

#include <atmoglobe/bench/Format.h>
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <thread>

namespace atmoglobe::bench {

volume::AntennaCoordinates FastInverse::operator()(const glm::dvec3& enu) const {
  const glm::dvec3 q(enu.x, enu.y, enu.z + rs + h0);
  const double horiz = std::hypot(q.x, q.y);
  const double rho = std::hypot(horiz, q.z);
  const double h = rho - rs;
  const double s = rs * std::atan2(horiz, q.z);
  const double a = s / re;
  const double x = (re + h) * std::sin(a), y = (re + h) * std::cos(a) - (re + h0);
  volume::AntennaCoordinates out;
  out.rangeMeters = std::hypot(x, y);
  out.elevationDeg = radiansToDegrees(std::atan2(y, x));
  double az = radiansToDegrees(std::atan2(q.x, q.y));
  if (az < 0.0) az += 360.0;
  out.azimuthDeg = az;
  return out;
}

glm::dvec3 FastInverse::forward(double rangeMeters, double azDeg, double elDeg) const {
  double h = 0.0, s = 0.0;
  volume::beamHeightAndGroundDistance(rangeMeters, elDeg, h0, re, &h, &s);
  const double g = s / rs, az = degreesToRadians(azDeg);
  return {(rs + h) * std::sin(g) * std::sin(az), (rs + h) * std::sin(g) * std::cos(az),
          (rs + h) * std::cos(g) - rs - h0};
}

FastInverse fastInverseFor(const volume::PolarVolume& v) {
  const double lat = degreesToRadians(v.site.latDeg);
  const double a = globe::kWgs84A, e2 = globe::kWgs84F * (2.0 - globe::kWgs84F);
  const double w = 1.0 - e2 * std::sin(lat) * std::sin(lat);
  const double m = a * (1.0 - e2) / std::pow(w, 1.5), n = a / std::sqrt(w);
  FastInverse f;
  f.rs = std::sqrt(m * n);
  f.h0 = v.site.antennaHeightEllipsoidMeters;
  f.re = volume::effectiveEarthRadiusMeters(v.beam, v.site.latDeg);
  return f;
}

InverseError measureFastInverseError(const volume::PolarVolume& v, const FastInverse& inverse, const glm::dvec3& lo,
                                     const glm::dvec3& hi, int samples, std::uint64_t seed) {
  InverseError err;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y), uz(lo.z, hi.z);
  const glm::dmat3 enu = globe::enuAxes(v.site.latDeg, v.site.lonDeg);
  const glm::dvec3 site = globe::geodeticToEcef({v.site.latDeg, v.site.lonDeg, v.site.antennaHeightEllipsoidMeters});
  for (int i = 0; i < samples; ++i) {
    const glm::dvec3 p(ux(rng), uy(rng), uz(rng));
    const volume::AntennaCoordinates f = inverse(p);
    if (f.rangeMeters > v.maxRangeMeters || f.rangeMeters < 1e3) continue;
    const volume::AntennaCoordinates e = volume::antennaCoordinatesExact(v.site, v.beam, site + enu * p);
    err.maxRangeMeters = std::max(err.maxRangeMeters, std::abs(f.rangeMeters - e.rangeMeters));
    double daz = std::abs(f.azimuthDeg - e.azimuthDeg);
    daz = std::min(daz, 360.0 - daz);
    err.maxAzimuthDeg = std::max(err.maxAzimuthDeg, daz);
    err.maxElevationDeg = std::max(err.maxElevationDeg, std::abs(f.elevationDeg - e.elevationDeg));
    ++err.points;
  }
  return err;
}

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
    why << "native " << formatG(g.nativeSpacingMeters) << " m would be "
        << formatG(std::ceil(ext.x / g.nativeSpacingMeters)) << " x "
        << formatG(std::ceil(ext.y / g.nativeSpacingMeters)) << " x "
        << formatG(std::ceil(ext.z / g.nativeSpacingMeters)) << " voxels (" << formatG(voxels * 4.0 / 1e9, 3)
        << " GB float32); limits: 2048 per side "
        << "(GL_MAX_3D_TEXTURE_SIZE) and " << formatG(maxVoxels * 4.0 / 1e9, 3) << " GB";
    g.coarsenedReason = why.str();
  }
  g.spacingMeters = spacing;
  g.nx = static_cast<int>(std::ceil(ext.x / spacing)) + 1;
  g.ny = static_cast<int>(std::ceil(ext.y / spacing)) + 1;
  g.nz = static_cast<int>(std::ceil(ext.z / spacing)) + 1;
  g.originEnu = lo;

  // Error of the fast inverse against the exact one, at random voxel centres inside the range.
  const InverseError err = measureFastInverseError(v, inv, lo, hi, 20000);
  g.maxRangeErrorMeters = err.maxRangeMeters;
  g.maxAzimuthErrorDeg = err.maxAzimuthDeg;
  g.maxElevationErrorDeg = err.maxElevationDeg;

  const auto t0 = std::chrono::steady_clock::now();
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
  g.resampleSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return g;
}

}  // namespace atmoglobe::bench
