#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/ParallelFor.h>
#include <atmoglobe/volume/Crop.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/Geolocation.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace atmoglobe::volume {

bool CropBox::containsLonLat(double latDeg, double lonDeg) const {
  if (latDeg < southDeg || latDeg > northDeg) return false;
  if (eastDeg - westDeg >= 360.0) return true;
  // Longitude east of the west edge, in [0, 360); the box spans (east - west) mod 360.
  const double span = std::fmod(std::fmod(eastDeg - westDeg, 360.0) + 360.0, 360.0);
  const double offset = std::fmod(std::fmod(lonDeg - westDeg, 360.0) + 360.0, 360.0);
  return offset <= span;
}

Status validateCropBox(const CropBox& b, const std::string& where) {
  if (!(b.southDeg >= -90.0 && b.northDeg <= 90.0 && b.southDeg < b.northDeg))
    return makeError(where + ": crop latitudes must satisfy -90 <= south < north <= 90");
  if (!(std::isfinite(b.westDeg) && std::isfinite(b.eastDeg) && std::abs(b.westDeg) <= 360.0 &&
        std::abs(b.eastDeg) <= 360.0))
    return makeError(where + ": crop longitudes must be finite degrees in -360..360");
  if (std::isnan(b.bottomMeters) || std::isnan(b.topMeters) || !(b.bottomMeters < b.topMeters))
    return makeError(where + ": crop heights must satisfy bottom < top (m above sea level)");
  return Ok{};
}

namespace {
template <typename T>
void rangeOfValues(const std::vector<float>& values, T& lo, T& hi) {
  lo = std::numeric_limits<float>::quiet_NaN();
  hi = std::numeric_limits<float>::quiet_NaN();
  for (float v : values) {
    if (!std::isfinite(v)) continue;
    if (!(lo <= v)) lo = v;
    if (!(hi >= v)) hi = v;
  }
}
}  // namespace

std::size_t cropGrid(GridVolume& g, const CropBox& box, const GeoidGrid* geoid) {
  std::size_t cut = 0;
  const bool lonLat = !box.coversEveryLonLat();
  const bool heights = !box.coversEveryHeight();
  if (!lonLat && !heights) return 0;
  const std::size_t plane = g.nx * g.ny;
  for (std::size_t j = 0; j < g.ny; ++j) {
    for (std::size_t i = 0; i < g.nx; ++i) {
      const double lat = g.latDegAt(j, i), lon = g.lonDegAt(j, i);
      const bool inside = !lonLat || box.containsLonLat(lat, lon);
      const double n = (heights && geoid) ? geoid->undulationMeters(lat, globe::wrapLongitudeDeg(lon)) : 0.0;
      for (std::size_t k = 0; k < g.nz; ++k) {
        const std::size_t idx = k * plane + j * g.nx + i;
        const double h = static_cast<double>(g.heightAboveEllipsoidMeters[idx]) - n;
        if (inside && h >= box.bottomMeters && h <= box.topMeters) continue;
        if (!std::isnan(g.values[idx])) ++cut;
        g.values[idx] = std::numeric_limits<float>::quiet_NaN();
      }
    }
  }
  rangeOfValues(g.values, g.valueMin, g.valueMax);
  return cut;
}

std::size_t cropPolar(PolarVolume& v, const CropBox& box, const GeoidGrid* geoid) {
  const bool heights = !box.coversEveryHeight();
  bool lonLat = !box.coversEveryLonLat();
  if (lonLat) {
    // Skip the geodesics when the whole range circle lies inside the box (its corners at the
    // maximum range, with a 1 % margin).
    const double r = v.maxRangeMeters * 1.01;
    bool allInside = true;
    for (double az = 0.0; az < 360.0 && allInside; az += 5.0) {
      const globe::GeodesicPoint p = globe::geodesicDirect(v.site.latDeg, v.site.lonDeg, az, r);
      allInside = box.containsLonLat(p.latDeg, p.lonDeg);
    }
    lonLat = !allInside;
  }
  if (!lonLat && !heights) return 0;
  const double n = geoid ? geoid->undulationMeters(v.site.latDeg, globe::wrapLongitudeDeg(v.site.lonDeg)) : 0.0;
  const double re = effectiveEarthRadiusMeters(v.beam, v.site.latDeg);
  std::vector<std::size_t> cutPerSweep(v.sweeps.size(), 0);
  auto sweep = [&](std::size_t k) {
    const PolarSweepLayout& s = v.sweeps[k];
    for (int g = 0; g < s.gateCount; ++g) {
      const double range = s.firstGateRangeMeters + s.gateSpacingMeters * g;
      double h = 0.0, ground = 0.0;
      beamHeightAndGroundDistance(range, s.elevationDeg, v.site.antennaHeightEllipsoidMeters, re, &h, &ground);
      const bool heightInside = h - n >= box.bottomMeters && h - n <= box.topMeters;
      for (int ray = 0; ray < s.rayCount; ++ray) {
        bool inside = heightInside;
        if (inside && lonLat) {
          const globe::GeodesicPoint p = globe::geodesicDirect(v.site.latDeg, v.site.lonDeg, s.azimuthDeg[ray], ground);
          inside = box.containsLonLat(p.latDeg, p.lonDeg);
        }
        if (inside) continue;
        float& value = v.values[(k * static_cast<std::size_t>(v.maxRays) + static_cast<std::size_t>(ray)) *
                                    static_cast<std::size_t>(v.maxGates) +
                                static_cast<std::size_t>(g)];
        if (!std::isnan(value)) ++cutPerSweep[k];
        value = std::numeric_limits<float>::quiet_NaN();
      }
    }
  };
  globe::parallelFor(v.sweeps.size(), sweep, 8);
  rangeOfValues(v.values, v.minValue, v.maxValue);
  std::size_t cut = 0;
  for (std::size_t c : cutPerSweep) cut += c;
  return cut;
}

}  // namespace atmoglobe::volume
