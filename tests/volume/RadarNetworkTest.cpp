// The coverage index and the overlap rules of a radar network (RadarNetwork.h): the index never
// leaves out a radar that has data at a point, the network's samples through the index equal those
// that visit every radar, and each rule gives the value worked out here from its formula.
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Mosaic.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/RadarNetwork.h>
#include <atmoglobe/volume/SliceSource.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <gtest/gtest.h>
#include <netcdf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <random>

namespace atmoglobe::volume {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A radar at (lat, lon) whose every gate holds `value` (dBZ): 36 rays, 100 gates of 1 km from 1 km,
// sweeps at 0.5, 1.5, 3, 6 and 10 deg.
PolarVolume constantRadar(double latDeg, double lonDeg, float value, double antennaMeters = 300.0) {
  RadarVolume rv;
  rv.format = "test";
  rv.sourcePath = "constant.nc";
  rv.beamWidthDeg = 1.0;
  rv.loadedField = FieldInfo{"DBZH", "dBZ", {}};
  rv.fields = {rv.loadedField};
  int index = 0;
  for (double el : {0.5, 1.5, 3.0, 6.0, 10.0}) {
    Sweep s;
    s.fixedAngleDeg = el;
    s.mode = SweepMode::Ppi;
    for (int r = 0; r < 36; ++r) s.azimuthDeg.push_back(10.0f * static_cast<float>(r) + 5.0f);
    s.elevationDeg.assign(s.azimuthDeg.size(), static_cast<float>(el));
    s.firstGateRangeMeters = 1000.0;
    s.gateSpacingMeters = 1000.0;
    s.gateCount = 100;
    s.values.assign(s.azimuthDeg.size() * s.gateCount, value);
    s.indexInFile = index++;
    rv.sweeps.push_back(std::move(s));
  }
  SiteResolution site;
  site.site = GeolocationSite{latDeg, lonDeg, antennaMeters};
  Result<PolarVolume> pv = buildPolarVolume(rv, site, BeamModel{});
  EXPECT_TRUE(pv.ok()) << (pv.ok() ? "" : pv.error());
  return pv.ok() ? *pv : PolarVolume{};
}

glm::dvec3 ecefOf(double latDeg, double lonDeg, double h) { return globe::geodeticToEcef({latDeg, lonDeg, h}); }

// Uniform random point in the ball of `s`.
glm::dvec3 pointInSphere(const BoundingSphere& s, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (;;) {
    const glm::dvec3 d(u(rng), u(rng), u(rng));
    if (glm::dot(d, d) <= 1.0) return s.centreEcef + s.radiusMeters * d;
  }
}

TEST(RadarNetwork, CoverageIndexListsEveryRadarWithDataAtAPoint) {
  // Spheres of radar size (40 to 470 km) at random places, with the hard ones added: across the
  // antimeridian, at a pole, next to a pole; random points inside each must find it listed.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> lat(-89.0, 89.0), lon(-180.0, 180.0), radius(40e3, 470e3);
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<BoundingSphere> spheres;
    if (trial == 0) {
      for (double l : {179.7, -179.6, 178.0, -176.0}) spheres.push_back({ecefOf(20.0, l, 500.0), 250e3});
    } else if (trial == 1) {
      spheres.push_back({ecefOf(90.0, 0.0, 100.0), 300e3});
      spheres.push_back({ecefOf(88.0, 120.0, 100.0), 300e3});
      spheres.push_back({ecefOf(-87.0, -60.0, 100.0), 200e3});
    } else {
      // A network over a region of 10-40 degrees, somewhere on the globe.
      const double lat0 = std::uniform_real_distribution<double>(-70.0, 70.0)(rng), lon0 = lon(rng);
      const double extent = std::uniform_real_distribution<double>(10.0, 40.0)(rng);
      for (int k = 0; k < 30; ++k) {
        const double la =
            std::clamp(lat0 + extent * (std::uniform_real_distribution<double>(-0.5, 0.5)(rng)), -89.0, 89.0);
        const double lo = lon0 + extent * std::uniform_real_distribution<double>(-0.5, 0.5)(rng);
        spheres.push_back({ecefOf(la, lo > 180.0 ? lo - 360.0 : lo, 300.0), radius(rng)});
      }
    }
    const CoverageIndex index = buildCoverageIndex(spheres);
    ASSERT_GT(index.cellCount(), 0u);
    std::size_t checked = 0;
    for (std::size_t k = 0; k < spheres.size(); ++k)
      for (int i = 0; i < 2000; ++i) {
        const glm::dvec3 p = pointInSphere(spheres[k], rng);
        const auto [first, last] = index.radarsAt(p);
        ASSERT_NE(first, last) << "trial " << trial << " sphere " << k << ": the point's cell lists nothing";
        ASSERT_NE(std::find(first, last, static_cast<std::uint32_t>(k)), last)
            << "trial " << trial << " sphere " << k << " is not listed at a point inside it";
        ++checked;
      }
    EXPECT_GT(checked, 0u);
    // The index is a filter, not the whole list: in a spread network a cell lists far fewer
    // radars than there are.
    if (trial >= 2) {
      EXPECT_LT(index.meanPerOccupiedCell(), 0.5 * static_cast<double>(spheres.size())) << "trial " << trial;
    }
  }
}

TEST(RadarNetwork, TheIndexTakesTheSameSamplesAsVisitingEveryRadar) {
  // Five overlapping radars of different values; the index only filters, so every rule gives the
  // same sample through it as over every radar.
  std::vector<PolarVolume> volumes;
  const double sites[5][2] = {{35.0, -97.0}, {35.2, -96.6}, {34.8, -96.7}, {35.5, -97.4}, {36.4, -95.0}};
  for (int k = 0; k < 5; ++k)
    volumes.push_back(constantRadar(sites[k][0], sites[k][1], 10.0f + 7.0f * static_cast<float>(k)));
  std::vector<const PolarVolume*> ptrs;
  for (const auto& v : volumes) ptrs.push_back(&v);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> lat(34.3, 36.9), lon(-97.9, -94.5), h(0.0, 3000.0);
  for (OverlapRule rule : {OverlapRule::WeightedMean, OverlapRule::LowestBeam, OverlapRule::Maximum}) {
    auto n = makeRadarNetworkSampler(ptrs, rule, FieldKind::Reflectivity, 0.1);
    ASSERT_TRUE(n.ok()) << n.error();
    int echoes = 0;
    for (int i = 0; i < 20000; ++i) {
      const glm::dvec3 p = ecefOf(lat(rng), lon(rng), h(rng));
      for (Interpolation interp : {Interpolation::Nearest, Interpolation::Linear}) {
        const VolumeSample a = (*n)->sample(p, interp), b = (*n)->sampleEveryRadar(p, interp);
        ASSERT_EQ(a.state, b.state) << toString(rule);
        ASSERT_EQ(a.value, b.value) << toString(rule);
        echoes += a.state == VolumeSample::State::Echo;
      }
    }
    EXPECT_GT(echoes, 1000) << toString(rule);  // the points do fall inside the radars
  }
}

// The step rule's cell crossing of a network: the smallest of the radars' that hold the point
// in their clip sphere, 0 where none does.
TEST(RadarNetwork, TheCellCrossingIsTheSmallestOfTheRadarsOverThePoint) {
  const PolarVolume a = constantRadar(35.0, -98.0, 30.0f), b = constantRadar(35.0, -97.0, 30.0f);
  auto net = makeRadarNetworkSampler({&a, &b}, OverlapRule::WeightedMean, FieldKind::Reflectivity);
  ASSERT_TRUE(net) << net.error();
  const PolarSampler sa(a), sb(b);
  const glm::dvec3 dir = glm::normalize(ecefOf(35.0, -97.5, 0.0));  // straight down, about
  int both = 0;
  for (double lon : {-98.3, -97.8, -97.5, -97.2, -96.7}) {
    const glm::dvec3 p = ecefOf(35.05, lon, 2000.0);
    const bool inA = glm::length(p - sa.boundingSphere().centreEcef) <= sa.boundingSphere().radiusMeters;
    const bool inB = glm::length(p - sb.boundingSphere().centreEcef) <= sb.boundingSphere().radiusMeters;
    double expected = 0.0;
    if (inA && inB) {
      expected = std::min(sa.cellCrossingMeters(p, dir), sb.cellCrossingMeters(p, dir));
      ++both;
    } else if (inA) {
      expected = sa.cellCrossingMeters(p, dir);
    } else if (inB) {
      expected = sb.cellCrossingMeters(p, dir);
    }
    EXPECT_GT(expected, 0.0) << "lon " << lon;  // every point is within 100 km of a radar
    EXPECT_DOUBLE_EQ((*net)->cellCrossingMeters(p, dir), expected) << "lon " << lon;
  }
  EXPECT_GE(both, 1);
  // 400 km from both: no radar holds it, no rule (the fixed step).
  EXPECT_EQ((*net)->cellCrossingMeters(ecefOf(39.0, -97.5, 2000.0), dir), 0.0);
}

TEST(RadarNetwork, EachRuleGivesItsFormulasValue) {
  // Two radars 60 km apart on the equator (A at 0.0 E holds 10 dBZ, B at 0.54 E holds 40).
  const PolarVolume a = constantRadar(0.0, 0.0, 10.0f), b = constantRadar(0.0, 0.54, 40.0f);
  std::vector<const PolarVolume*> both{&a, &b};
  auto sampler = [&](OverlapRule rule) {
    auto n = makeRadarNetworkSampler(both, rule, FieldKind::Reflectivity);
    EXPECT_TRUE(n.ok()) << n.error();
    return std::move(*n);
  };
  auto mean = sampler(OverlapRule::WeightedMean), lowest = sampler(OverlapRule::LowestBeam),
       maximum = sampler(OverlapRule::Maximum);
  for (double lonDeg : {0.12, 0.2, 0.27, 0.35, 0.42}) {
    const glm::dvec3 p = ecefOf(0.0, lonDeg, 1200.0);
    const AntennaCoordinates ca = antennaCoordinatesExact(a.site, a.beam, p);
    const AntennaCoordinates cb = antennaCoordinatesExact(b.site, b.beam, p);
    // Both radars see the point (between their lowest and highest beams).
    ASSERT_EQ(PolarSampler(a).sample(p, Interpolation::Linear).state, VolumeSample::State::Echo);
    ASSERT_EQ(PolarSampler(b).sample(p, Interpolation::Linear).state, VolumeSample::State::Echo);
    const double wa = std::exp(-std::pow(ca.rangeMeters / 50000.0, 2.0));
    const double wb = std::exp(-std::pow(cb.rangeMeters / 50000.0, 2.0));
    const VolumeSample m = mean->sample(p, Interpolation::Linear);
    ASSERT_EQ(m.state, VolumeSample::State::Echo);
    EXPECT_NEAR(m.value, (10.0 * wa + 40.0 * wb) / (wa + wb), 1e-4) << lonDeg;  // float gates
    // Linear interpolation of equal gates: the value up to the rounding of its weights.
    EXPECT_NEAR(maximum->sample(p, Interpolation::Linear).value, 40.0, 1e-12);
    // The lowest beam over the point is the nearer radar's (same antenna height, same angles);
    // at 0.27 E the two are equally far and the tie goes to the first.
    const double expected =
        ca.rangeMeters < cb.rangeMeters - 1.0 ? 10.0 : (cb.rangeMeters < ca.rangeMeters - 1.0 ? 40.0 : 10.0);
    EXPECT_NEAR(lowest->sample(p, Interpolation::Linear).value, expected, 1e-12) << lonDeg;
    EXPECT_EQ(*lowest->leadingRadar(p, Interpolation::Linear), expected == 10.0 ? 0u : 1u) << lonDeg;
  }
  // Where one radar alone has data, every rule gives its sample.
  const glm::dvec3 onlyA = ecefOf(0.0, -0.5, 1500.0);  // 56 km from A, 116 km from B (range 100 km)
  const VolumeSample alone = PolarSampler(a).sample(onlyA, Interpolation::Linear);
  ASSERT_EQ(alone.state, VolumeSample::State::Echo);
  for (auto* n : {mean.get(), lowest.get(), maximum.get()}) {
    EXPECT_EQ(n->sample(onlyA, Interpolation::Linear).state, alone.state);
    EXPECT_EQ(n->sample(onlyA, Interpolation::Linear).value, alone.value);
  }
  // Beyond both: no data.
  EXPECT_EQ(mean->sample(ecefOf(3.0, 3.0, 1000.0), Interpolation::Linear).state, VolumeSample::State::NoData);
}

TEST(RadarNetwork, TheLowestBeamFollowsAntennaHeightNotJustDistance) {
  // A mountain-top radar (3000 m) 10 km nearer than a valley radar (0 m): over a point between
  // them the valley radar's lowest beam passes about 2.9 km lower (it starts 3 km lower; 10 km
  // more distance at 0.5 deg raises it by about 90 m), so its value wins although it is farther.
  const PolarVolume mountain = constantRadar(0.0, 0.0, 20.0f, 3000.0), valley = constantRadar(0.0, 0.4, 30.0f, 0.0);
  std::vector<const PolarVolume*> both{&mountain, &valley};
  auto n = makeRadarNetworkSampler(both, OverlapRule::LowestBeam, FieldKind::Reflectivity);
  ASSERT_TRUE(n.ok()) << n.error();
  const glm::dvec3 p = ecefOf(0.0, 0.155, 3400.0);  // 17 km from the mountain, 27 km from the valley
  ASSERT_EQ(PolarSampler(mountain).sample(p, Interpolation::Linear).state, VolumeSample::State::Echo);
  ASSERT_EQ(PolarSampler(valley).sample(p, Interpolation::Linear).state, VolumeSample::State::Echo);
  EXPECT_NEAR((*n)->sample(p, Interpolation::Linear).value, 30.0, 1e-12);
}

TEST(RadarNetwork, RulesThatCannotGiveAValueAreRefused) {
  const PolarVolume a = constantRadar(0.0, 0.0, 10.0f);
  std::vector<const PolarVolume*> one{&a};
  auto integrate = makeRadarNetworkSampler(one, OverlapRule::Integrate, FieldKind::Reflectivity);
  ASSERT_FALSE(integrate.ok());
  EXPECT_NE(integrate.error().find("integrate"), std::string::npos) << integrate.error();
  auto velocity = makeRadarNetworkSampler(one, OverlapRule::WeightedMean, FieldKind::Velocity);
  ASSERT_FALSE(velocity.ok());
  EXPECT_NE(velocity.error().find("cannot be combined"), std::string::npos) << velocity.error();
  EXPECT_FALSE(makeRadarNetworkSampler({}, OverlapRule::Maximum, FieldKind::Reflectivity).ok());
  EXPECT_FALSE(parseOverlapRule("average").ok());
  EXPECT_EQ(*parseOverlapRule("lowest"), OverlapRule::LowestBeam);
}

}  // namespace
}  // namespace atmoglobe::volume

// A mosaic (Mosaic.h) of two SYNTHETIC radars whose storms are one analytic field (synth --sites:
// syntheticNetworkDbz), written as CF netCDF and read back: at every node with a value, the mosaic
// is within the radars' own sampling error there of the field. The mean of values each within e
// of the field is within e of it, so the bound per node is the largest |radar sample - field|
// over the radars that echo there (plus the float storage, 1e-5 dB).
namespace atmoglobe::volume {
namespace {

TEST(RadarNetwork, AMosaicOfOneAnalyticFieldIsThatFieldWithinTheRadarsSamplingError) {
  const std::filesystem::path dir = atmoglobe_test::freshTestDir("radar_network_mosaic");
  const std::vector<std::pair<std::string, std::array<double, 3>>> sites = {{"KTLX", {35.333056, -97.277778, 384.7}},
                                                                            {"KVNX", {36.740833, -98.127778, 378.6}}};
  std::vector<std::pair<double, double>> latLon;
  for (const auto& s : sites) latLon.emplace_back(s.second[0], s.second[1]);
  SyntheticRadarOptions base;
  base.noiseDbz = 0.0;
  base.gateSpacingMeters = 1000.0;
  base.firstGateRangeMeters = 2125.0;
  base.networkStorms = syntheticNetworkStorms(latLon, 230.0 + 250.0, 3);
  std::vector<std::shared_ptr<const PolarVolume>> layouts;
  std::vector<const PolarVolume*> raw;
  MosaicMetadata meta;
  meta.field = "DBZ";
  meta.units = "dBZ";
  meta.kind = FieldKind::Reflectivity;
  for (const auto& [id, where] : sites) {
    SyntheticRadarOptions o = base;
    o.siteId = id;
    o.siteLatDeg = where[0];
    o.siteLonDeg = where[1];
    o.antennaAltitudeMslMeters = where[2];
    const std::string path = (dir / (id + ".nc")).string();
    ASSERT_TRUE(writeSyntheticCfRadial(path, o).ok());
    RadarLoadOptions load;
    load.buildRenderLayout = true;
    load.useGeoid = false;  // the synthetic gates' heights are MSL heights of an antenna at MSL height
    auto r = loadRadar(path, load);
    ASSERT_TRUE(r) << r.error();
    layouts.push_back(std::make_shared<const PolarVolume>(std::move(*r->layout)));
    raw.push_back(layouts.back().get());
    meta.radars.push_back({id, o.startTimeIso8601, path, where[0], where[1]});
  }
  auto net = makeRadarNetworkSampler(raw, OverlapRule::WeightedMean, FieldKind::Reflectivity);
  ASSERT_TRUE(net.ok()) << net.error();
  // Heights: the radars were read without the geoid (their MSL heights taken as ellipsoidal, as the
  // synthetic writer's field takes them), so the grid is given above the ellipsoid too.
  RegularGridSpec spec;
  spec.westDeg = -98.6;
  spec.eastDeg = -96.8;
  spec.southDeg = 35.0;
  spec.northDeg = 37.0;
  spec.bottomMeters = 1000.0;
  spec.topMeters = 9000.0;
  spec.nx = 37;
  spec.ny = 41;
  spec.nz = 9;
  spec.datum = HeightDatum::Ellipsoid;
  auto values = resampleRegular(**net, spec, Interpolation::Linear, nullptr);
  ASSERT_TRUE(values.ok()) << values.error();
  // The writer takes heights above mean sea level: written with the spec relabelled (the check
  // below reads the values back and compares them node by node; the datum is the test's own).
  RegularGridSpec msl = spec;
  msl.datum = HeightDatum::MeanSeaLevel;
  const std::string out = (dir / "mosaic.nc").string();
  ASSERT_TRUE(writeMosaicNetcdf(out, msl, *values, meta).ok());
  int ncid = -1, varid = -1;
  ASSERT_EQ(nc_open(out.c_str(), NC_NOWRITE, &ncid), NC_NOERR);
  ASSERT_EQ(nc_inq_varid(ncid, "DBZ", &varid), NC_NOERR);
  std::vector<float> back(spec.sampleCount());
  ASSERT_EQ(nc_get_var_float(ncid, varid, back.data()), NC_NOERR);
  nc_close(ncid);
  // Drawn back as a grid layer, the file is labelled a mosaic of its rule, not a forecast.
  EXPECT_EQ(mosaicOverlapRule(out), toString(meta.rule));
  EXPECT_EQ(mosaicOverlapRule(meta.radars.front().path), "") << "a radar volume is no mosaic";

  std::size_t nodes = 0, both = 0, edges = 0;
  double worstExcess = 0.0;
  std::vector<double> errors;
  for (std::size_t k = 0; k < spec.nz; ++k)
    for (std::size_t j = 0; j < spec.ny; ++j)
      for (std::size_t i = 0; i < spec.nx; ++i) {
        const float v = back[(k * spec.ny + j) * spec.nx + i];
        if (!std::isfinite(v)) continue;
        const double lon = spec.westDeg + (spec.eastDeg - spec.westDeg) * double(i) / double(spec.nx - 1);
        const double lat = spec.southDeg + (spec.northDeg - spec.southDeg) * double(j) / double(spec.ny - 1);
        const double h = spec.bottomMeters + (spec.topMeters - spec.bottomMeters) * double(k) / double(spec.nz - 1);
        const glm::dvec3 p = globe::geodeticToEcef({lat, lon, h});
        const double exact = syntheticNetworkDbz(base, lat, lon, h, base.startTimeIso8601);
        // No storm reaches the node: a radar's echo there is the edge of its interpolation
        // between gates with and without echo (not a value of the field to compare with).
        if (!std::isfinite(exact)) {
          ++edges;
          continue;
        }
        double bound = 0.0;
        int echoes = 0;
        for (const PolarVolume* r : raw) {
          const VolumeSample s = PolarSampler(*r).sample(p, Interpolation::Linear);
          if (s.state != VolumeSample::State::Echo) continue;
          bound = std::max(bound, std::fabs(s.value - exact));
          ++echoes;
        }
        ASSERT_GT(echoes, 0) << "a mosaic value where no radar echoes";
        ++nodes;
        both += echoes == 2;
        const double err = std::fabs(v - exact);
        errors.push_back(err);
        worstExcess = std::max(worstExcess, err - bound);
      }
  std::sort(errors.begin(), errors.end());
  ASSERT_GT(nodes, 200u);
  std::cout << "mosaic of one field: " << nodes << " nodes with a value (" << both << " seen by both radars, " << edges
            << " beyond every storm), |mosaic - "
            << "field| median " << errors[errors.size() / 2] << " dB, 95th percentile "
            << errors[errors.size() * 95 / 100] << " dB, max " << errors.back() << " dB; beyond the radars' own "
            << "sampling error by at most " << worstExcess << " dB\n";
  EXPECT_GT(both, 50u) << "the radars must overlap over the grid";
  EXPECT_LE(worstExcess, 1e-4);  // float storage of the values (|v| < 100 dBZ: 1e-5) and of the weights
}

}  // namespace
}  // namespace atmoglobe::volume
