#pragma once
// In-memory synthetic radar volumes for the renderer tests (no file, no ../shared): PPI sweeps at
// 1-degree steps, regular rays and gates, a field given as a function of antenna coordinates.
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <memory>

namespace atmoglobe::testutil {

struct SyntheticPolarGeometry {
  double latDeg = 33.654;  ///< Lubbock's coordinates by default
  double lonDeg = -101.814;
  double antennaHeightMeters = 1029.0;  ///< above the WGS84 ellipsoid
  int sweeps = 10;                      ///< at 0.5, 1.5, ... deg
  int rays = 360;                       ///< centred at (ray + 0.5) * 360 / rays deg
  std::uint32_t gates = 400;
  double firstGateMeters = 2125.0;
  double gateSpacingMeters = 250.0;
};

/// field(rangeMeters, azimuthDeg, elevationDeg) at each gate centre.
inline volume::RadarVolume syntheticRadarVolume(const SyntheticPolarGeometry& g,
                                                const std::function<float(double, double, double)>& field) {
  volume::RadarVolume v;
  v.format = "synthetic";
  v.sourcePath = "synthetic";
  v.site = {"TEST", g.latDeg, g.lonDeg, g.antennaHeightMeters, volume::HeightDatum::Ellipsoid, {}};
  v.beamWidthDeg = 1.0;
  v.loadedField = {"DBZ", "dBZ", {}};
  v.fields = {v.loadedField};
  for (int k = 0; k < g.sweeps; ++k) {
    volume::Sweep s;
    s.indexInFile = k;
    s.fixedAngleDeg = 0.5 + k;
    s.firstGateRangeMeters = g.firstGateMeters;
    s.gateSpacingMeters = g.gateSpacingMeters;
    s.gateCount = g.gates;
    for (int ray = 0; ray < g.rays; ++ray) {
      const double az = (ray + 0.5) * 360.0 / g.rays;
      s.azimuthDeg.push_back(static_cast<float>(az));
      s.elevationDeg.push_back(static_cast<float>(s.fixedAngleDeg));
      for (std::uint32_t gate = 0; gate < s.gateCount; ++gate)
        s.values.push_back(field(s.gateRangeMeters(gate), az, s.fixedAngleDeg));
    }
    v.sweeps.push_back(std::move(s));
  }
  return v;
}

/// The render layout of a synthetic volume (its height is already ellipsoidal: no geoid).
inline volume::PolarVolume polarOf(const volume::RadarVolume& radar) {
  volume::SiteResolution site;
  site.site = {radar.site.latDeg, radar.site.lonDeg, radar.site.antennaHeightMeters};
  auto p = volume::buildPolarVolume(radar, site, volume::BeamModel{});
  EXPECT_TRUE(p) << (p ? "" : p.error());
  return p ? *p : volume::PolarVolume{};
}

/// A radar at (latDeg, lonDeg), antenna 400 m above the ellipsoid, seeing a field given at
/// geodetic places: field(latDeg, lonDeg, heightMeters) at each gate centre (the exact geolocation,
/// 4/3 Earth). 8 sweeps 0.5..7.5 deg, 180 rays, 240 gates of 500 m (to 122 km): the networks'
/// test radars.
inline std::shared_ptr<const volume::PolarVolume> radarSeeingField(
    double latDeg, double lonDeg, const std::function<float(double, double, double)>& field) {
  SyntheticPolarGeometry g;
  g.latDeg = latDeg;
  g.lonDeg = lonDeg;
  g.antennaHeightMeters = 400.0;
  g.sweeps = 8;
  g.rays = 180;
  g.gates = 240;
  g.gateSpacingMeters = 500.0;
  const volume::GeolocationSite site{latDeg, lonDeg, g.antennaHeightMeters};
  return std::make_shared<const volume::PolarVolume>(
      polarOf(syntheticRadarVolume(g, [&](double r, double az, double el) {
        const volume::GatePosition p = volume::geolocateGateExact(site, volume::BeamModel{}, az, el, r);
        return field(p.latDeg, p.lonDeg, p.heightMeters);
      })));
}

}  // namespace atmoglobe::testutil
