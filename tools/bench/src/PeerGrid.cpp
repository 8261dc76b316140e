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
  const double a = globe::kWgs84A, e2 = globe::kWgs84E2;
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
  {
    const double native = g.nativeSpacingMeters;
    g = layoutPeerGrid(lo, hi, native, maxVoxels);
  }
  const double spacing = g.spacingMeters;

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

PeerGrid layoutPeerGrid(const glm::dvec3& lo, const glm::dvec3& hi, double nativeSpacingMeters, double maxVoxels) {
  PeerGrid g;
  g.nativeSpacingMeters = nativeSpacingMeters;
  const glm::dvec3 ext = hi - lo;
  double spacing = nativeSpacingMeters;
  const double maxSide = std::max({ext.x, ext.y, ext.z}) / spacing;
  const double voxels = (ext.x / spacing) * (ext.y / spacing) * (ext.z / spacing);
  const double coarsen = std::max({1.0, maxSide / 2047.0, std::cbrt(voxels / maxVoxels)});
  if (coarsen > 1.0) {
    spacing *= coarsen;
    std::ostringstream why;
    why << "native " << formatG(nativeSpacingMeters) << " m would be "
        << formatG(std::ceil(ext.x / nativeSpacingMeters)) << " x " << formatG(std::ceil(ext.y / nativeSpacingMeters))
        << " x " << formatG(std::ceil(ext.z / nativeSpacingMeters)) << " voxels (" << formatG(voxels * 4.0 / 1e9, 3)
        << " GB float32); limits: 2048 per side "
        << "(GL_MAX_3D_TEXTURE_SIZE) and " << formatG(maxVoxels * 4.0 / 1e9, 3) << " GB";
    g.coarsenedReason = why.str();
  }
  g.spacingMeters = spacing;
  g.nx = static_cast<int>(std::ceil(ext.x / spacing)) + 1;
  g.ny = static_cast<int>(std::ceil(ext.y / spacing)) + 1;
  g.nz = static_cast<int>(std::ceil(ext.z / spacing)) + 1;
  g.originEnu = lo;
  return g;
}

PeerFrame enuFrameAt(double latDeg, double lonDeg, double heightMeters) {
  return {globe::geodeticToEcef({latDeg, lonDeg, heightMeters}), globe::enuAxes(latDeg, lonDeg)};
}

bool gridPeerBox(const volume::GridVolume& grid, const PeerFrame& frame, double visibleAbove, glm::dvec3* lo,
                 glm::dvec3* hi, double* nativeSpacingMeters) {
  glm::dvec3 a(std::numeric_limits<double>::infinity()), b(-std::numeric_limits<double>::infinity());
  double finest = std::numeric_limits<double>::infinity(), horizontal = 0.0;
  for (std::size_t j = 0; j < grid.ny; ++j)
    for (std::size_t i = 0; i < grid.nx; ++i) {
      bool any = false;
      for (std::size_t k = 0; k < grid.nz; ++k) {
        if (!(grid.value(k, j, i) > visibleAbove)) continue;
        any = true;
        const glm::dvec3 p =
            frame.toEnu(globe::geodeticToEcef({grid.latDegAt(j, i), grid.lonDegAt(j, i), grid.heightMeters(k, j, i)}));
        a = glm::min(a, p), b = glm::max(b, p);
        if (k + 1 < grid.nz)
          finest = std::min(finest, double(grid.heightMeters(k + 1, j, i) - grid.heightMeters(k, j, i)));
        if (k > 0) finest = std::min(finest, double(grid.heightMeters(k, j, i) - grid.heightMeters(k - 1, j, i)));
      }
      if (!any || horizontal > 0.0) continue;
      // The grid's horizontal spacing where the data are: the larger distance to the next column or row.
      const std::size_t i1 = i + 1 < grid.nx ? i + 1 : i - 1, j1 = j + 1 < grid.ny ? j + 1 : j - 1;
      const glm::dvec3 p0 = globe::geodeticToEcef({grid.latDegAt(j, i), grid.lonDegAt(j, i), 0.0});
      horizontal = std::max(glm::length(globe::geodeticToEcef({grid.latDegAt(j, i1), grid.lonDegAt(j, i1), 0.0}) - p0),
                            glm::length(globe::geodeticToEcef({grid.latDegAt(j1, i), grid.lonDegAt(j1, i), 0.0}) - p0));
    }
  if (!std::isfinite(a.x)) return false;
  *lo = a - horizontal;
  *hi = b + horizontal;
  *nativeSpacingMeters = std::isfinite(finest) ? finest : horizontal;
  return true;
}

void resampleSampler(const volume::VolumeSampler& sampler, const PeerFrame& frame, PeerGrid& g, double emptyValue,
                     int threads, std::vector<float>* values) {
  const auto t0 = std::chrono::steady_clock::now();
  g.frameOriginEcef = frame.originEcef;
  g.frameEnuToEcef = frame.enuToEcef;
  values->assign(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny) * static_cast<std::size_t>(g.nz),
                 static_cast<float>(emptyValue));
  auto work = [&](int first) {
    for (int k = first; k < g.nz; k += threads)
      for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
          const glm::dvec3 p = frame.toEcef(g.originEnu + g.spacingMeters * glm::dvec3(i, j, k));
          const volume::VolumeSample s = sampler.sample(p, volume::Interpolation::Linear);
          if (s.state == volume::VolumeSample::State::Echo)
            (*values)[(static_cast<std::size_t>(k) * static_cast<std::size_t>(g.ny) + static_cast<std::size_t>(j)) *
                          static_cast<std::size_t>(g.nx) +
                      static_cast<std::size_t>(i)] = static_cast<float>(s.value);
        }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, threads); ++t) pool.emplace_back(work, t);
  for (auto& t : pool) t.join();
  g.resampleSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double trilinearAt(const PeerGrid& g, const std::vector<float>& values, const glm::dvec3& enu, double emptyValue) {
  const glm::dvec3 u = (enu - g.originEnu) / g.spacingMeters;
  if (!(u.x >= 0.0 && u.y >= 0.0 && u.z >= 0.0 && u.x <= g.nx - 1 && u.y <= g.ny - 1 && u.z <= g.nz - 1))
    return emptyValue;
  const int i = std::min(static_cast<int>(u.x), std::max(0, g.nx - 2));
  const int j = std::min(static_cast<int>(u.y), std::max(0, g.ny - 2));
  const int k = std::min(static_cast<int>(u.z), std::max(0, g.nz - 2));
  const glm::dvec3 f = u - glm::dvec3(i, j, k);
  auto at = [&](int a, int b, int c) {
    a = std::min(a, g.nx - 1), b = std::min(b, g.ny - 1), c = std::min(c, g.nz - 1);
    return double(values[(static_cast<std::size_t>(c) * static_cast<std::size_t>(g.ny) + static_cast<std::size_t>(b)) *
                             static_cast<std::size_t>(g.nx) +
                         static_cast<std::size_t>(a)]);
  };
  double v = 0.0;
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        v += (dx ? f.x : 1 - f.x) * (dy ? f.y : 1 - f.y) * (dz ? f.z : 1 - f.z) * at(i + dx, j + dy, k + dz);
  return v;
}

void measureReconstructionError(const volume::VolumeSampler& sampler, const PeerFrame& frame, PeerGrid& g,
                                const std::vector<float>& values, double emptyValue, double floorValue, int samples,
                                std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const glm::dvec3 hi = g.originEnu + g.spacingMeters * glm::dvec3(g.nx - 1, g.ny - 1, g.nz - 1);
  std::uniform_real_distribution<double> ux(g.originEnu.x, hi.x), uy(g.originEnu.y, hi.y), uz(g.originEnu.z, hi.z);
  double maxErr = 0.0, sum2 = 0.0;
  for (int n = 0; n < samples; ++n) {
    const glm::dvec3 p(ux(rng), uy(rng), uz(rng));
    const volume::VolumeSample s = sampler.sample(frame.toEcef(p), volume::Interpolation::Linear);
    const double truth = s.state == volume::VolumeSample::State::Echo ? s.value : emptyValue;
    const double e =
        std::abs(std::max(trilinearAt(g, values, p, emptyValue), floorValue) - std::max(truth, floorValue));
    maxErr = std::max(maxErr, e);
    sum2 += e * e;
  }
  g.maxReconstructionError = maxErr;
  g.rmsReconstructionError = samples > 0 ? std::sqrt(sum2 / samples) : 0.0;
  g.reconstructionPoints = samples;
}

double trilinearErrorBound(double spacingMeters, double sumMaxSecondDerivatives) {
  return spacingMeters * spacingMeters / 8.0 * sumMaxSecondDerivatives;
}

}  // namespace atmoglobe::bench
