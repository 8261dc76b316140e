// The synthetic CfRadial writer: read back through our own reader, checked against the CfRadial
// conventions (netCDF-C API and, where installed, ncdump -h), the site from the OURadar station
// file, the storm model at each gate's exactly geolocated position, and atomic writing.
//
// Independent references used here:
//  - KTLX coordinates: the OURadar station file (OURadar/radar-data,
//    OURadar_nexrad-locations.json), "KTLX": latitude 35.33305555555556, longitude
//    -97.27777777777777, elevation 369.7224, height 15.0 (python3 json, see StationListTest);
//    antenna altitude = elevation + height. The values are written out below so that the suite
//    runs without the sample data; SiteIsKtlxOfTheOuRadarFile (label realdata) reads the file
//    itself with nlohmann::json (not through our StationList code).
//  - Gate count: by hand, 2125 m + k * 250 m <= 230000 m -> k <= 911.5 -> 912 gates; last gate
//    centre 2125 + 911 * 250 = 229875 m.
//  - Gate positions: geolocateGateExact (GeographicLib Geodesic::Direct) and back to the site-
//    centred azimuthal-equidistant plane with GeographicLib Geodesic::Inverse; the writer does
//    neither (it uses the closed-form ground distance and s sin az, s cos az).
#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <gtest/gtest.h>
#include <netcdf.h>
#include <GeographicLib/Geodesic.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace atmoglobe::volume {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "synthetic" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// KTLX in the OURadar station file (see the top).
constexpr double kKtlxLatDeg = 35.33305555555556;
constexpr double kKtlxLonDeg = -97.27777777777777;
constexpr double kKtlxElevationMeters = 369.7224;
constexpr double kKtlxTowerMeters = 15.0;

// Files written once for the suite: the default volume and a noise-free one.
struct Written {
  std::string defaultPath, quietPath;
  SyntheticRadarSummary defaultSummary, quietSummary;
  double defaultSeconds = 0;
};

const Written& written() {
  static const Written w = [] {
    Written r;
    const fs::path dir = freshDir("suite");
    r.defaultPath = (dir / "synthetic_ktlx.nc").string();
    r.quietPath = (dir / "synthetic_quiet.nc").string();
    const auto t0 = std::chrono::steady_clock::now();
    const Status a = writeSyntheticCfRadial(r.defaultPath, SyntheticRadarOptions{}, &r.defaultSummary);
    r.defaultSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_TRUE(a.ok()) << (a.ok() ? "" : a.error());
    SyntheticRadarOptions quiet;
    quiet.noiseDbz = 0.0;
    const Status b = writeSyntheticCfRadial(r.quietPath, quiet, &r.quietSummary);
    EXPECT_TRUE(b.ok()) << (b.ok() ? "" : b.error());
    return r;
  }();
  return w;
}

RadarVolume mustRead(const std::string& path) {
  auto r = readRadarVolume(path, ReadOptions{});
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error());
  if (!r.ok()) return {};
  return std::move(r).value();
}

GeolocationSite siteMsl(const SyntheticRadarOptions& o) {
  // The antenna's MSL height used as the datum: gate heights come out above MSL, which is what
  // the storm model takes (see SyntheticRadar.h).
  return GeolocationSite{o.siteLatDeg, o.siteLonDeg, o.antennaAltitudeMslMeters};
}

TEST(SyntheticRadar, ReadsBackWithVcp212GeometryAtKtlx) {
  const Written& w = written();
  const RadarVolume v = mustRead(w.defaultPath);
  EXPECT_EQ(v.format, "CfRadial");
  EXPECT_EQ(v.site.name, "KTLX");
  EXPECT_EQ(v.timeIso8601, "2020-05-01T21:00:00Z");
  EXPECT_EQ(v.loadedField.name, "DBZ");
  EXPECT_EQ(v.loadedField.units, "dBZ");
  // WSR-88D beam width 0.95 deg (NOAA WDTB Distance Learning Operations Course, topic 3 lesson 1,
  // fig. 17); stored as float: 1e-6 covers the narrowing.
  EXPECT_NEAR(v.beamWidthDeg, 0.95, 1e-6);

  // Site: the OURadar file's KTLX record (see the top). Stored as doubles: exact round trip
  // expected, 1e-9 deg / 1e-9 m allow for nothing but print noise.
  EXPECT_NEAR(v.site.latDeg, kKtlxLatDeg, 1e-9);
  EXPECT_NEAR(v.site.lonDeg, kKtlxLonDeg, 1e-9);
  EXPECT_NEAR(v.site.antennaHeightMeters, kKtlxElevationMeters + kKtlxTowerMeters, 1e-9);
  EXPECT_EQ(v.site.heightDatum, HeightDatum::MeanSeaLevel);

  // 14 sweeps at the VCP 212 angles (those of VCP 12, same source), float-stored: 1e-5 deg.
  const double vcp212[14] = {0.5, 0.9, 1.3, 1.8, 2.4, 3.1, 4.0, 5.1, 6.4, 8.0, 10.0, 12.5, 15.6, 19.5};
  ASSERT_EQ(v.sweeps.size(), 14u);
  for (std::size_t s = 0; s < 14; ++s) {
    const Sweep& sw = v.sweeps[s];
    EXPECT_NEAR(sw.fixedAngleDeg, vcp212[s], 1e-5) << s;
    EXPECT_EQ(sw.mode, SweepMode::Ppi);
    ASSERT_EQ(sw.rayCount(), 360u) << s;
    EXPECT_EQ(sw.gateCount, 912u) << s;
    EXPECT_NEAR(sw.firstGateRangeMeters, 2125.0, 1e-3);  // float-exact values: 1e-3 m is print noise only
    EXPECT_NEAR(sw.gateSpacingMeters, 250.0, 1e-6);
    EXPECT_NEAR(sw.gateRangeMeters(911), 229875.0, 1e-3);
    // Every 1-degree sector holds exactly one ray, centred on k + 0.5 deg.
    std::vector<float> az = sw.azimuthDeg;
    std::sort(az.begin(), az.end());
    for (std::size_t k = 0; k < 360; ++k) EXPECT_NEAR(az[k], static_cast<double>(k) + 0.5, 1e-4) << s << " " << k;
    for (float e : sw.elevationDeg) EXPECT_NEAR(e, vcp212[s], 1e-5);
    EXPECT_EQ(sw.values.size(), 360u * 912u);
  }
  // Size: "a few MB" (deflated shorts); timing printed for the report.
  std::printf("synthetic default volume: %.2f MB, written in %.2f s, %zu echo gates, max %.2f dBZ\n",
              static_cast<double>(w.defaultSummary.fileBytes) / 1e6, w.defaultSeconds, w.defaultSummary.echoGates,
              w.defaultSummary.maxDbz);
  EXPECT_EQ(w.defaultSummary.fileBytes, fs::file_size(w.defaultPath));
  EXPECT_LT(w.defaultSummary.fileBytes, 6u * 1000u * 1000u);
}

// The KTLX record written out above, against the OURadar file itself.
TEST(SyntheticRadar, SiteIsKtlxOfTheOuRadarFile) {
  const std::string path = atmoglobe_test::testDataPath("stations/OURadar_nexrad-locations.json");
  SKIP_WITHOUT_TEST_DATA(path);
  std::ifstream in(path);
  ASSERT_TRUE(in.good()) << path;
  const nlohmann::json j = nlohmann::json::parse(in);
  const auto& ktlx = j.at("KTLX");
  EXPECT_EQ(ktlx.at("latitude").get<double>(), kKtlxLatDeg);  // the same decimal text: the same double
  EXPECT_EQ(ktlx.at("longitude").get<double>(), kKtlxLonDeg);
  EXPECT_EQ(ktlx.at("elevation").get<double>(), kKtlxElevationMeters);
  EXPECT_EQ(ktlx.at("height").get<double>(), kKtlxTowerMeters);
  const SyntheticRadarOptions o;
  EXPECT_NEAR(o.siteLatDeg, ktlx.at("latitude").get<double>(), 1e-9);  // print noise only, as above
  EXPECT_NEAR(o.siteLonDeg, ktlx.at("longitude").get<double>(), 1e-9);
  EXPECT_NEAR(o.antennaAltitudeMslMeters, ktlx.at("elevation").get<double>() + ktlx.at("height").get<double>(), 1e-9);
}

TEST(SyntheticRadar, MaximumIsNearTheRequestedStormCentre) {
  const Written& w = written();
  const RadarVolume v = mustRead(w.defaultPath);
  const SyntheticRadarOptions o;
  double best = -1e9;
  const Sweep* bestSweep = nullptr;
  std::size_t bestRay = 0;
  std::uint32_t bestGate = 0;
  std::size_t echoes = 0;
  for (const Sweep& sw : v.sweeps) {
    for (std::size_t r = 0; r < sw.rayCount(); ++r) {
      for (std::uint32_t g = 0; g < sw.gateCount; ++g) {
        const float x = sw.value(r, g);
        if (!isMeasuredValue(x)) continue;
        ++echoes;
        if (x > best) best = x, bestSweep = &sw, bestRay = r, bestGate = g;
      }
    }
  }
  ASSERT_NE(bestSweep, nullptr);
  EXPECT_EQ(echoes, w.defaultSummary.echoGates);
  EXPECT_GE(best, 55.0);
  EXPECT_LE(best, 70.0);
  EXPECT_NEAR(best, w.defaultSummary.maxDbz, 1e-4);  // float storage of a 0.01-dB step value
  const GatePosition p = geolocateGateExact(siteMsl(o), BeamModel{}, bestSweep->azimuthDeg[bestRay],
                                            bestSweep->elevationDeg[bestRay], bestSweep->gateRangeMeters(bestGate));
  // The requested centre: the geodesic from the site with azimuth atan2(E, N), length hypot(E, N).
  const auto& geod = GeographicLib::Geodesic::WGS84();
  double cLat = 0, cLon = 0;
  geod.Direct(o.siteLatDeg, o.siteLonDeg, radiansToDegrees(std::atan2(o.stormEastKm, o.stormNorthKm)),
              std::hypot(o.stormEastKm, o.stormNorthKm) * 1000.0, cLat, cLon);
  double distMeters = 0;
  geod.Inverse(cLat, cLon, p.latDeg, p.lonDeg, distMeters);
  // 4 km: the core falls 22 dB per (d/6 km)^2, so +4 sigma of 1-dB noise can lift a gate at most
  // 2.6 km from the axis to the top; the axis tilts < 0.4 km below 2 km; rays are 1.1 km apart
  // at 62 km (half: 0.55 km). A misplaced storm (wrong sign, swapped axes) misses by > 70 km.
  EXPECT_LT(distMeters, 4000.0) << "max " << best << " dBZ at " << p.latDeg << ", " << p.lonDeg;
  EXPECT_LT(p.heightMeters - o.antennaAltitudeMslMeters, 3000.0);  // low-level maximum
}

TEST(SyntheticRadar, NoEchoFarFromTheStorm) {
  const RadarVolume v = mustRead(written().defaultPath);
  // The storm is to the SW (bearing ~234 deg, 62 km), its anvil goes ENE, its stratiform area N:
  // the south-east quadrant beyond 90 km holds nothing in the model (at least ~700 dB below the
  // threshold there), so every gate must be the fill value (kNoData).
  std::size_t checked = 0, echoes = 0;
  for (const Sweep& sw : v.sweeps) {
    for (std::size_t r = 0; r < sw.rayCount(); ++r) {
      if (sw.azimuthDeg[r] < 100.0f || sw.azimuthDeg[r] > 200.0f) continue;
      for (std::uint32_t g = 0; g < sw.gateCount; ++g) {
        if (sw.gateRangeMeters(g) < 90000.0) continue;
        ++checked;
        if (!isNoData(sw.value(r, g))) ++echoes;
      }
    }
  }
  EXPECT_GT(checked, 100000u);
  EXPECT_EQ(echoes, 0u);
}

// Every gate of the noise-free file holds the model at that gate's exactly geolocated position.
TEST(SyntheticRadar, ValuesAreTheModelAtGeolocatedGatePositions) {
  const Written& w = written();
  const RadarVolume v = mustRead(w.quietPath);
  SyntheticRadarOptions o;
  o.noiseDbz = 0.0;
  const GeolocationSite site = siteMsl(o);
  const auto& geod = GeographicLib::Geodesic::WGS84();
  std::size_t echoesChecked = 0, emptyChecked = 0;
  double worst = 0;
  for (const Sweep& sw : v.sweeps) {
    for (std::size_t r = 0; r < sw.rayCount(); r += 3) {
      for (std::uint32_t g = 0; g < sw.gateCount; g += 2) {
        const GatePosition p =
            geolocateGateExact(site, BeamModel{}, sw.azimuthDeg[r], sw.elevationDeg[r], sw.gateRangeMeters(g));
        double s12 = 0, azi1 = 0, azi2 = 0;
        geod.Inverse(o.siteLatDeg, o.siteLonDeg, p.latDeg, p.lonDeg, s12, azi1, azi2);
        const double east = s12 * std::sin(degreesToRadians(azi1)), north = s12 * std::cos(degreesToRadians(azi1));
        const double model = syntheticStormDbz(o, east, north, p.heightMeters);
        const float got = sw.value(r, g);
        // Stored in 0.01-dB counts (rounding: 0.005 dB) as float (< 1e-5 dB at < 100 dBZ); the two
        // position paths agree to ~1e-8 m, worth < 1e-9 dB at the model's steepest (~0.3 dB/m
        // nowhere; ~0.03 dB/m at the bright band). So 0.006 dB; gates within it of the
        // threshold could go either way and are not judged.
        if (model >= o.minEchoDbz + 0.006) {
          ASSERT_TRUE(isMeasuredValue(got)) << "gate " << g << " ray " << r << " model " << model;
          worst = std::max(worst, std::fabs(got - model));
          ++echoesChecked;
        } else if (model < o.minEchoDbz - 0.006 || !std::isfinite(model)) {
          EXPECT_TRUE(isNoData(got)) << "gate " << g << " ray " << r << " model " << model << " got " << got;
          ++emptyChecked;
        }
      }
    }
  }
  EXPECT_LE(worst, 0.006);
  EXPECT_GT(echoesChecked, 10000u);
  EXPECT_GT(emptyChecked, 100000u);
}

// A network field (synth --sites): two overlapping radars (KTLX, and KVNX 173 km away) written with
// the storms of one field; every gate of both holds the exact field at its geolocated position, so
// where they overlap they agree. The writer maps gates into each storm's plane through geodesics at
// nodes every 10 km of each ray and interpolates between them: positions within about
// spacing^2 / (8 R) = 2 m of the exact ones, worth up to 0.06 dB at the model's steepest
// (~0.03 dB/m, the bright band); with the 0.006 dB of storage, 0.07 dB. Measured: 0.0050 dB, the
// storage rounding alone.
TEST(SyntheticRadar, NetworkVolumesHoldTheSameFieldWhereTheyOverlap) {
  const fs::path dir = freshDir("network");
  const std::vector<std::pair<std::string, std::array<double, 3>>> sites = {{"KTLX", {35.333056, -97.277778, 384.7}},
                                                                            {"KVNX", {36.740833, -98.127778, 378.6}}};
  std::vector<std::pair<double, double>> latLon;
  for (const auto& s : sites) latLon.emplace_back(s.second[0], s.second[1]);
  SyntheticRadarOptions base;
  base.noiseDbz = 0.0;
  base.raysPerSweep = 120;
  base.gateSpacingMeters = 1000.0;
  base.elevationsDeg = {0.5, 1.8, 4.0, 8.0};
  base.networkStorms = syntheticNetworkStorms(latLon, 230.0 + 250.0, 3);
  ASSERT_GE(base.networkStorms.size(), 2u);
  double worst = 0.0;
  std::vector<std::size_t> echoes;
  for (const auto& [id, where] : sites) {
    echoes.push_back(0);
    SyntheticRadarOptions o = base;
    o.siteId = id;
    o.siteLatDeg = where[0];
    o.siteLonDeg = where[1];
    o.antennaAltitudeMslMeters = where[2];
    const std::string path = (dir / (id + ".nc")).string();
    const Status st = writeSyntheticCfRadial(path, o);
    ASSERT_TRUE(st.ok()) << st.error();
    const RadarVolume v = mustRead(path);
    const GeolocationSite site = siteMsl(o);
    for (const Sweep& sw : v.sweeps)
      for (std::size_t r = 0; r < sw.rayCount(); ++r)
        for (std::uint32_t g = 0; g < sw.gateCount; ++g) {
          const GatePosition p =
              geolocateGateExact(site, BeamModel{}, sw.azimuthDeg[r], sw.elevationDeg[r], sw.gateRangeMeters(g));
          const double exact = syntheticNetworkDbz(o, p.latDeg, p.lonDeg, p.heightMeters, o.startTimeIso8601);
          const float got = sw.value(r, g);
          if (exact >= o.minEchoDbz + 0.07) {
            ASSERT_TRUE(isMeasuredValue(got)) << id << " gate " << g << " ray " << r << " exact " << exact;
            worst = std::max(worst, std::fabs(got - exact));
            ++echoes.back();
          } else if (exact < o.minEchoDbz - 0.07 || !std::isfinite(exact)) {
            EXPECT_TRUE(isNoData(got)) << id << " gate " << g << " ray " << r << " exact " << exact;
          }
        }
  }
  std::cout << "network field: " << echoes[0] << " and " << echoes[1] << " echo gates, worst " << worst
            << " dB from the exact field\n";
  EXPECT_LE(worst, 0.07);
  EXPECT_GT(echoes[0], 1000u);
  EXPECT_GT(echoes[1], 1000u);
}

// The model's structure as SyntheticRadar.h describes it (dBZ at points in the site plane).
TEST(SyntheticRadar, StormModelHasCoreAnvilWeakEchoRegionAndBrightBand) {
  SyntheticRadarOptions o;
  const double cx = o.stormEastKm * 1000.0, cy = o.stormNorthKm * 1000.0;
  // Core: 55-65 dBZ at 1 km at the centre; echo top (18 dBZ) between 12 and 14 km over the tilted core.
  const double low = syntheticStormDbz(o, cx, cy, 1000.0);
  EXPECT_GE(low, 55.0);
  EXPECT_LE(low, 65.0);
  auto coreTop = [&](double zMeters) {  // the core is displaced 0.35 km/km towards bearing 60
    const double t = 0.35 * (zMeters - 1000.0);
    return syntheticStormDbz(o, cx + t * std::sin(kPi / 3), cy + t * std::cos(kPi / 3), zMeters);
  };
  EXPECT_GE(coreTop(12000.0), 18.0);
  EXPECT_LT(coreTop(14000.0), 18.0);
  EXPECT_LT(coreTop(15000.0), 5.0);
  // Weak-echo region: at 4 km, 5 km SE of the core axis, >= 15 dB weaker than at the same
  // distance NW of it (the hole is 30 dB deep at its centre).
  const double t4 = 0.35 * 3000.0;
  const double ax = cx + t4 * std::sin(kPi / 3), ay = cy + t4 * std::cos(kPi / 3);
  const double d = 5000.0 / std::sqrt(2.0);
  EXPECT_GE(syntheticStormDbz(o, ax - d, ay + d, 4000.0) - syntheticStormDbz(o, ax + d, ay - d, 4000.0), 15.0);
  // Anvil: 40 km downwind at 10.5 km: 15-25 dBZ; nothing at 10.5 km 40 km upwind.
  const double down = syntheticStormDbz(o, cx + 40000.0 * std::sin(kPi / 3), cy + 40000.0 * std::cos(kPi / 3), 10500.0);
  EXPECT_GE(down, 15.0);
  EXPECT_LE(down, 25.0);
  EXPECT_LT(syntheticStormDbz(o, cx - 40000.0 * std::sin(kPi / 3), cy - 40000.0 * std::cos(kPi / 3), 10500.0), 5.0);
  // Stratiform centre (+(-5, +45) km): rain 20-35 dBZ at 2 km; the profile's maximum between
  // 1 and 8 km lies in the bright band 3.5-4.1 km and is >= 5 dB above the rain below it.
  const double sx = cx - 5000.0, sy = cy + 45000.0;
  const double rain = syntheticStormDbz(o, sx, sy, 2000.0);
  EXPECT_GE(rain, 20.0);
  EXPECT_LE(rain, 35.0);
  double bestZ = 0, bestV = -1e9;
  for (double z = 1000.0; z <= 8000.0; z += 10.0) {
    const double val = syntheticStormDbz(o, sx, sy, z);
    if (val > bestV) bestV = val, bestZ = z;
  }
  EXPECT_GE(bestZ, 3500.0);
  EXPECT_LE(bestZ, 4100.0);
  EXPECT_GE(bestV - rain, 5.0);
  EXPECT_LT(syntheticStormDbz(o, sx, sy, 7000.0), rain);  // snow above is weaker than the rain
}

TEST(SyntheticRadar, FileFollowsCfRadialConventions) {
  const std::string path = written().defaultPath;
  int nc = -1;
  ASSERT_EQ(nc_open(path.c_str(), NC_NOWRITE, &nc), NC_NOERR);
  int fmt = 0;
  ASSERT_EQ(nc_inq_format(nc, &fmt), NC_NOERR);
  EXPECT_EQ(fmt, NC_FORMAT_NETCDF4);
  auto dimLen = [&](const char* name) {
    int id = -1;
    std::size_t len = 0;
    if (nc_inq_dimid(nc, name, &id) != NC_NOERR || nc_inq_dimlen(nc, id, &len) != NC_NOERR) return std::size_t{0};
    return len;
  };
  EXPECT_EQ(dimLen("time"), 14u * 360u);
  EXPECT_EQ(dimLen("range"), 912u);
  EXPECT_EQ(dimLen("sweep"), 14u);
  auto varShape = [&](const char* name, nc_type* type) {
    std::string dims;
    int id = -1, nd = 0;
    int ids[NC_MAX_VAR_DIMS];
    if (nc_inq_varid(nc, name, &id) != NC_NOERR) return std::string("missing");
    nc_inq_vartype(nc, id, type);
    nc_inq_varndims(nc, id, &nd);
    nc_inq_vardimid(nc, id, ids);
    for (int i = 0; i < nd; ++i) {
      char n[NC_MAX_NAME + 1];
      nc_inq_dimname(nc, ids[i], n);
      if (i) dims.push_back(',');  // not ("," + string): GCC 12 misreports -Wrestrict on that
      dims.append(n);
    }
    return dims;
  };
  auto textAttr = [&](const char* var, const char* name) {
    int id = NC_GLOBAL;
    if (var && nc_inq_varid(nc, var, &id) != NC_NOERR) return std::string("missing variable");
    std::size_t len = 0;
    if (nc_inq_attlen(nc, id, name, &len) != NC_NOERR) return std::string("missing attribute");
    std::string s(len, '\0');
    nc_get_att_text(nc, id, name, s.data());
    return s;
  };
  struct Expect {
    const char* name;
    nc_type type;
    const char* dims;
  };
  // CfRadial 1.4 format document (NCAR/UCAR): coordinate, sweep and per-ray variables with their
  // dimensions.
  const Expect expected[] = {
      {"time", NC_DOUBLE, "time"},
      {"range", NC_FLOAT, "range"},
      {"latitude", NC_DOUBLE, ""},
      {"longitude", NC_DOUBLE, ""},
      {"altitude", NC_DOUBLE, ""},
      {"sweep_number", NC_INT, "sweep"},
      {"sweep_mode", NC_CHAR, "sweep,string_length"},
      {"fixed_angle", NC_FLOAT, "sweep"},
      {"sweep_start_ray_index", NC_INT, "sweep"},
      {"sweep_end_ray_index", NC_INT, "sweep"},
      {"azimuth", NC_FLOAT, "time"},
      {"elevation", NC_FLOAT, "time"},
      {"radar_beam_width_h", NC_FLOAT, ""},
      {"radar_beam_width_v", NC_FLOAT, ""},
      {"time_coverage_start", NC_CHAR, "string_length"},
      {"DBZ", NC_SHORT, "time,range"},
  };
  for (const Expect& e : expected) {
    nc_type t = NC_NAT;
    EXPECT_EQ(varShape(e.name, &t), e.dims) << e.name;
    EXPECT_EQ(t, e.type) << e.name;
  }
  EXPECT_EQ(textAttr(nullptr, "Conventions"), "CF/Radial instrument_parameters");
  EXPECT_EQ(textAttr(nullptr, "version"), "1.4");
  EXPECT_EQ(textAttr(nullptr, "instrument_name"), "KTLX");
  EXPECT_NE(textAttr(nullptr, "title").find("SYNTHETIC"), std::string::npos);
  EXPECT_NE(textAttr(nullptr, "comment").find("SYNTHETIC data generated by atmoglobe"), std::string::npos);
  EXPECT_EQ(textAttr("time", "units"), "seconds since 2020-05-01T21:00:00Z");
  EXPECT_EQ(textAttr("range", "units"), "meters");
  EXPECT_EQ(textAttr("DBZ", "units"), "dBZ");
  EXPECT_NE(textAttr("DBZ", "comment").find("SYNTHETIC"), std::string::npos);
  int dbz = -1;
  ASSERT_EQ(nc_inq_varid(nc, "DBZ", &dbz), NC_NOERR);
  short fill = 0;
  float scale = 0, offset = 1;
  EXPECT_EQ(nc_get_att_short(nc, dbz, "_FillValue", &fill), NC_NOERR);
  EXPECT_EQ(nc_get_att_float(nc, dbz, "scale_factor", &scale), NC_NOERR);
  EXPECT_EQ(nc_get_att_float(nc, dbz, "add_offset", &offset), NC_NOERR);
  EXPECT_EQ(fill, -32768);
  EXPECT_FLOAT_EQ(scale, 0.01f);
  EXPECT_EQ(offset, 0.0f);
  // Sweep index table: contiguous, 0-based, inclusive.
  int starts[14], ends[14];
  int vs = -1, ve = -1;
  ASSERT_EQ(nc_inq_varid(nc, "sweep_start_ray_index", &vs), NC_NOERR);
  ASSERT_EQ(nc_inq_varid(nc, "sweep_end_ray_index", &ve), NC_NOERR);
  ASSERT_EQ(nc_get_var_int(nc, vs, starts), NC_NOERR);
  ASSERT_EQ(nc_get_var_int(nc, ve, ends), NC_NOERR);
  for (int s = 0; s < 14; ++s) {
    EXPECT_EQ(starts[s], s * 360);
    EXPECT_EQ(ends[s], s * 360 + 359);
  }
  nc_close(nc);

  // netCDF-C's own dump tool, where installed (Debian netcdf-bin), as a second reader of the header.
  if (std::FILE* pipe = ::popen(("ncdump -h '" + path + "' 2>/dev/null").c_str(), "r")) {
    std::string header;
    char buf[4096];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) header.append(buf, n);
    const int rc = ::pclose(pipe);
    if (rc == 0 && !header.empty()) {
      for (const char* needle : {"time = 5040 ;", "range = 912 ;", "sweep = 14 ;", "short DBZ(time, range) ;",
                                 "DBZ:_FillValue = -32768s ;", "DBZ:scale_factor = 0.01f ;", "double latitude ;",
                                 "int sweep_start_ray_index(sweep) ;", "char sweep_mode(sweep, string_length) ;",
                                 "float fixed_angle(sweep) ;", ":Conventions = \"CF/Radial instrument_parameters\" ;"})
        EXPECT_NE(header.find(needle), std::string::npos) << "ncdump -h lacks: " << needle;
    }
  }
}

TEST(SyntheticRadar, SameSeedSameFileDifferentSeedDifferentNoise) {
  const fs::path dir = freshDir("seed");
  SyntheticRadarOptions o;
  o.elevationsDeg = {0.5, 2.4};
  auto values = [&](std::uint64_t seed, const char* name) {
    o.seed = seed;
    const std::string p = (dir / name).string();
    EXPECT_TRUE(writeSyntheticCfRadial(p, o).ok());
    std::vector<float> all;
    for (const Sweep& sw : mustRead(p).sweeps) all.insert(all.end(), sw.values.begin(), sw.values.end());
    return all;
  };
  const auto a = values(7, "a.nc"), b = values(7, "b.nc"), c = values(8, "c.nc");
  ASSERT_EQ(a.size(), 2u * 360u * 912u);
  std::size_t sameAB = 0, sameAC = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sameAB += (a[i] == b[i]) || (isNoData(a[i]) && isNoData(b[i]));
    sameAC += (a[i] == c[i]) || (isNoData(a[i]) && isNoData(c[i]));
  }
  EXPECT_EQ(sameAB, a.size());
  EXPECT_LT(sameAC, a.size());
}

TEST(SyntheticRadar, FailedWriteLeavesNothingAndSaysWhy) {
  const fs::path dir = freshDir("atomic");
  SyntheticRadarOptions o;
  o.elevationsDeg = {0.5};
  // 1. The directory does not exist.
  const std::string missing = (dir / "no-such-dir" / "x.nc").string();
  Status st = writeSyntheticCfRadial(missing, o);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find(missing), std::string::npos) << st.error();
  EXPECT_NE(st.error().find("No such file or directory"), std::string::npos) << st.error();
  // 2. The parent is a regular file (unwritable as a directory even for root).
  { std::ofstream(dir / "plain") << "x"; }
  st = writeSyntheticCfRadial((dir / "plain" / "x.nc").string(), o);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("Not a directory"), std::string::npos) << st.error();
  // 3. Failure at the very end: the whole file is written to the temporary, then the rename
  //    fails because the target is a directory. The temporary must be gone.
  fs::create_directories(dir / "target.nc");
  st = writeSyntheticCfRadial((dir / "target.nc").string(), o);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("rename"), std::string::npos) << st.error();
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"plain", "target.nc"}));
  EXPECT_TRUE(fs::is_empty(dir / "target.nc"));
  // 4. An existing file is replaced whole; no temporaries remain.
  { std::ofstream(dir / "old.nc") << "old contents"; }
  ASSERT_TRUE(writeSyntheticCfRadial((dir / "old.nc").string(), o).ok());
  EXPECT_GT(fs::file_size(dir / "old.nc"), 1000u);
  EXPECT_EQ(mustRead((dir / "old.nc").string()).sweeps.size(), 1u);
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 3u);
}

TEST(SyntheticRadar, BadOptionsAreErrors) {
  const fs::path dir = freshDir("bad");
  SyntheticRadarOptions o;
  o.siteLatDeg = 95.0;
  Status st = writeSyntheticCfRadial((dir / "x.nc").string(), o);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("latitude 95"), std::string::npos) << st.error();
  o = SyntheticRadarOptions{};
  o.elevationsDeg = {};
  EXPECT_FALSE(validateSyntheticRadarOptions(o).ok());
  o = SyntheticRadarOptions{};
  o.gateSpacingMeters = 10.0;  // 22788 gates: over the 4096 cap
  EXPECT_FALSE(validateSyntheticRadarOptions(o).ok());
  o = SyntheticRadarOptions{};
  o.startTimeIso8601 = "yesterday";
  EXPECT_FALSE(validateSyntheticRadarOptions(o).ok());
  EXPECT_TRUE(fs::is_empty(dir));  // options are checked before anything is created
}

}  // namespace
}  // namespace atmoglobe::volume
