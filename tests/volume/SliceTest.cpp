// Slices (volume/Slice.h, SliceSource.h): the geometry puts each pixel where it says, the values
// are the samplers' own, the geodesic path is GeographicLib's, the synthetic storm shows up at
// its heights, and bad requests are refused with a clear message.
#include "SyntheticGridVolume.h"
#include "SyntheticPolarVolume.h"

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/GridSampler.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/Slice.h>
#include <atmoglobe/volume/SliceSource.h>
#include <atmoglobe/volume/SyntheticGrid.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <gtest/gtest.h>
#include <GeographicLib/Geodesic.hpp>

#include <cmath>
#include <iostream>

namespace {

using namespace atmoglobe;
using volume::Interpolation;
using volume::SliceGeometry;
using volume::VolumeSample;

// The raster's encoding of a sample (Slice.h: NaN no data, -inf no echo, else the value).
void expectSameSample(float pixel, const VolumeSample& s, const std::string& where) {
  switch (s.state) {
    case VolumeSample::State::NoData: EXPECT_TRUE(std::isnan(pixel)) << where; break;
    case VolumeSample::State::NoEcho: EXPECT_TRUE(std::isinf(pixel) && pixel < 0) << where; break;
    case VolumeSample::State::Echo: EXPECT_EQ(pixel, static_cast<float>(s.value)) << where; break;
  }
}

}  // namespace

// GeodesicPath: its length is the sum of GeographicLib's inverse distances; the points it gives
// lie on those geodesics at the distances asked for.
TEST(Slice, GeodesicPathLengthMatchesGeographicLibInverse) {
  const std::vector<volume::LatLon> points{{35.33, -97.28}, {36.9, -95.1}, {37.5, -99.0}, {-12.0, 170.0}};
  auto path = volume::GeodesicPath::create(points);
  ASSERT_TRUE(path) << path.error();
  const auto& geod = GeographicLib::Geodesic::WGS84();
  double sum = 0.0;
  for (std::size_t k = 1; k < points.size(); ++k) {
    double s12 = 0.0;
    geod.Inverse(points[k - 1].latDeg, points[k - 1].lonDeg, points[k].latDeg, points[k].lonDeg, s12);
    sum += s12;
    // Each point sits at its cumulative distance (GeographicLib's direct/inverse agree to ~15 nm).
    EXPECT_NEAR(path->pointDistancesMeters()[k], sum, 1e-6);
    const globe::GeodesicPoint p = path->at(path->pointDistancesMeters()[k]);
    double back = 0.0;
    geod.Inverse(p.latDeg, p.lonDeg, points[k].latDeg, points[k].lonDeg, back);
    EXPECT_LT(back, 1e-6) << "point " << k;
  }
  EXPECT_NEAR(path->lengthMeters(), sum, 1e-6);
  // A point inside segment 3 is at the asked distance from that segment's start, on its line: its
  // distances to both ends add up to the segment's length.
  const double d0 = path->pointDistancesMeters()[2], d1 = path->pointDistancesMeters()[3];
  const double d = d0 + 0.37 * (d1 - d0);
  const globe::GeodesicPoint mid = path->at(d);
  double a = 0.0, b = 0.0;
  geod.Inverse(points[2].latDeg, points[2].lonDeg, mid.latDeg, mid.lonDeg, a);
  geod.Inverse(mid.latDeg, mid.lonDeg, points[3].latDeg, points[3].lonDeg, b);
  EXPECT_NEAR(a, d - d0, 1e-6);
  EXPECT_NEAR(a + b, d1 - d0, 1e-6);
}

// A cross-section through a grid holding a field linear in latitude, longitude and height: every
// pixel is the sampler's sample at the pixel's position, and that is the field there.
TEST(Slice, CrossSectionThroughAnalyticGridMatchesDirectSamples) {
  auto field = [](double lat, double lon, double h) { return 3.0 * (lat - 35.0) + 2.0 * (lon + 97.0) + 0.002 * h; };
  const volume::GridVolume g = testutil::rectilinearGrid(
      testutil::evenlySpaced(-99.0, 0.25, 17), testutil::evenlySpaced(34.0, 0.25, 13),
      {0.0, 500.0, 1500.0, 3000.0, 6000.0, 10000.0, 16000.0}, [](double, double) { return 200.0; }, field);
  const volume::GridSampler sampler(g);
  volume::CrossSectionSpec spec;
  spec.points = {{34.2, -98.8}, {36.7, -95.3}, {35.1, -95.2}};
  spec.bottomMeters = 0.0;
  spec.topMeters = 17000.0;
  spec.datum = volume::SliceHeightDatum::Ellipsoid;
  spec.columns = 120;
  spec.rows = 50;
  auto geometry = SliceGeometry::crossSection(spec, nullptr);
  ASSERT_TRUE(geometry) << geometry.error();
  const volume::SliceRaster r = volume::sampleSlice({&sampler}, *geometry, Interpolation::Linear, 3);
  ASSERT_EQ(r.columns, 120);
  ASSERT_EQ(r.rows, 50);
  double worst = 0.0;
  std::size_t echo = 0, empty = 0;
  for (int j = 0; j < r.rows; ++j)
    for (int i = 0; i < r.columns; ++i) {
      const globe::Geodetic p = geometry->geodeticAt(i + 0.5, j + 0.5);
      // The pixel's position: the path's point at its distance, at its row's height.
      const globe::GeodesicPoint onPath = geometry->path().at((i + 0.5) / r.columns * geometry->path().lengthMeters());
      ASSERT_DOUBLE_EQ(p.latDeg, onPath.latDeg);
      ASSERT_NEAR(p.heightMeters, 17000.0 * (1.0 - (j + 0.5) / r.rows), 1e-9);
      const VolumeSample s = sampler.sample(globe::geodeticToEcef(p), Interpolation::Linear);
      expectSameSample(r.at(i, j), s, "pixel " + std::to_string(i) + "," + std::to_string(j));
      if (s.state == VolumeSample::State::Echo) {
        worst = std::max(worst, std::abs(r.at(i, j) - field(p.latDeg, p.lonDeg, p.heightMeters)));
        ++echo;
      } else {
        ++empty;
      }
    }
  std::cout << "cross-section: " << echo << " echo pixels, " << empty << " empty; worst |pixel - field| " << worst
            << "\n";
  // The path leaves the grid (east of -95 deg) and the heights run below its lowest level (200 m)
  // and above its top (16.2 km): both kinds of pixels exist.
  EXPECT_GT(echo, 1000u);
  EXPECT_GT(empty, 100u);
  EXPECT_EQ(r.echoCount, echo);
  // Values and level heights are floats (~6e-8 relative of values < 40 and of 16 km: 2.4e-6 and
  // 1 mm -> 2e-6 in the field); the pixel is narrowed to float (2e-6); the ECEF round trip ~1e-9 m.
  EXPECT_LT(worst, 2e-5);
}

// A CAPPI of a synthetic radar volume: every pixel is the PolarSampler's sample at the pixel's
// latitude/longitude at the CAPPI height, above the ellipsoid or above sea level (EGM96) as asked.
TEST(Slice, CappiOfSyntheticRadarEqualsSamplerValues) {
  testutil::SyntheticPolarGeometry geo;
  const volume::RadarVolume radar = testutil::syntheticRadarVolume(geo, [](double r, double az, double el) {
    if (r > 60000.0 && r < 70000.0) return -std::numeric_limits<float>::infinity();  // a no-echo ring
    return static_cast<float>(10.0 + r / 5000.0 + 5.0 * std::sin(az * M_PI / 180.0) + el);
  });
  const volume::PolarVolume polar = testutil::polarOf(radar);
  const volume::PolarSampler sampler(polar);
  const auto& geoid = volume::defaultEgm96Grid();
  ASSERT_TRUE(geoid) << geoid.error();
  for (const auto datum : {volume::SliceHeightDatum::Ellipsoid, volume::SliceHeightDatum::SeaLevel}) {
    volume::CappiSpec spec;
    spec.heightMeters = 3000.0;
    spec.datum = datum;
    spec.box = volume::polarExtent(polar);
    spec.columns = 90;
    spec.rows = 70;
    auto geometry = SliceGeometry::cappi(spec, &*geoid);
    ASSERT_TRUE(geometry) << geometry.error();
    const volume::SliceRaster r = volume::sampleSlice({&sampler}, *geometry, Interpolation::Linear);
    for (int j = 0; j < r.rows; ++j)
      for (int i = 0; i < r.columns; ++i) {
        const double lat = spec.box.northDeg - (j + 0.5) / r.rows * (spec.box.northDeg - spec.box.southDeg);
        const double lon = spec.box.westDeg + (i + 0.5) / r.columns * (spec.box.eastDeg - spec.box.westDeg);
        const double n = datum == volume::SliceHeightDatum::SeaLevel ? geoid->undulationMeters(lat, lon) : 0.0;
        const globe::Geodetic p = geometry->geodeticAt(i + 0.5, j + 0.5);
        ASSERT_NEAR(p.latDeg, lat, 1e-12);
        ASSERT_NEAR(p.lonDeg, lon, 1e-12);
        ASSERT_NEAR(p.heightMeters, 3000.0 + n, 1e-9);
        expectSameSample(r.at(i, j),
                         sampler.sample(globe::geodeticToEcef({lat, lon, 3000.0 + n}), Interpolation::Linear),
                         "pixel " + std::to_string(i) + "," + std::to_string(j));
      }
    // At 3 km the beams reach from ~40 km (the 4 deg sweep) to ~170 km (the 0.5 deg sweep's lower
    // edge): echoes, the no-echo ring and no data beyond are all there.
    EXPECT_GT(r.echoCount, 500u);
    EXPECT_GT(r.noEchoCount, 50u);
    EXPECT_GT(r.noDataCount, 500u);
  }
}

// Several samplers: the largest echo wins, no echo beats no data (Slice.h's rule).
TEST(Slice, SeveralSamplersCombineByTheOneRule) {
  auto flat = [](double value) {
    return testutil::rectilinearGrid(
        testutil::evenlySpaced(10.0, 1.0, 3), testutil::evenlySpaced(40.0, 1.0, 3), {0.0, 5000.0},
        [](double, double) { return 0.0; }, [value](double, double, double) { return value; });
  };
  const volume::GridVolume a = flat(5.0), b = flat(7.0);
  const volume::GridSampler sa(a), sb(b);
  const glm::dvec3 inside = globe::geodeticToEcef({41.0, 11.0, 1000.0});
  const glm::dvec3 outside = globe::geodeticToEcef({41.0, 11.0, 9000.0});
  EXPECT_EQ(volume::sampleVolumes({&sa, &sb}, inside, Interpolation::Linear).value, 7.0);
  EXPECT_EQ(volume::sampleVolumes({&sb, &sa}, inside, Interpolation::Linear).value, 7.0);
  EXPECT_EQ(volume::sampleVolumes({&sa, &sb}, outside, Interpolation::Linear).state, VolumeSample::State::NoData);
}

namespace {
// The synthetic radar volume without noise, written once per process.
const std::string& quietSyntheticRadar() {
  static const std::string path = [] {
    const std::string p = ATMOGLOBE_TEST_OUTPUT_DIR + "/slice_synthetic_ktlx.nc";
    volume::SyntheticRadarOptions o;
    o.noiseDbz = 0.0;
    EXPECT_TRUE(volume::writeSyntheticCfRadial(p, o).ok());
    return p;
  }();
  return path;
}
}  // namespace

// A vertical cross-section of the synthetic radar volume through its supercell shows echoes at
// the heights the storm model has them: the 20 dBZ echo top along the path is the model's within
// the radar's vertical resolution there, and the core's peak is the model's within what linear
// interpolation between sweeps loses.
TEST(Slice, RadarCrossSectionShowsTheSyntheticStormAtItsHeights) {
  volume::SliceSourceOptions load;
  load.path = quietSyntheticRadar();
  auto source = volume::SliceSource::load(load);
  ASSERT_TRUE(source) << source.error();
  EXPECT_TRUE((*source)->synthetic());
  EXPECT_EQ((*source)->name(), "KTLX");
  EXPECT_EQ((*source)->validTime(), "2020-05-01T21:00:00Z");
  const volume::SyntheticRadarOptions o;
  // Through the storm's low-level core (stormEastKm, stormNorthKm from the site), 30 km either
  // side along the storm's motion (bearing 60 deg).
  const double coreAzimuth = std::atan2(o.stormEastKm, o.stormNorthKm) * 180.0 / M_PI;
  const double coreDistance = std::hypot(o.stormEastKm, o.stormNorthKm) * 1000.0;
  const globe::GeodesicPoint core = globe::geodesicDirect(o.siteLatDeg, o.siteLonDeg, coreAzimuth, coreDistance);
  const globe::GeodesicPoint a = globe::geodesicDirect(core.latDeg, core.lonDeg, 240.0, 30000.0);
  const globe::GeodesicPoint b = globe::geodesicDirect(core.latDeg, core.lonDeg, 60.0, 30000.0);
  volume::SliceRequest request;
  request.cappi = false;
  request.path = {{a.latDeg, a.lonDeg}, {b.latDeg, b.lonDeg}};
  request.bottomMeters = 0.0;
  request.topMeters = 18000.0;
  request.columns = 120;
  request.rows = 180;  // 100 m rows
  auto geometry = volume::sliceGeometryFor(**source, request);
  ASSERT_TRUE(geometry) << geometry.error();
  auto raster = volume::sampleSource(**source, *geometry);
  ASSERT_TRUE(raster) << raster.error();
  const auto& geoid = volume::defaultEgm96Grid();
  ASSERT_TRUE(geoid);
  const volume::PolarVolume& polar = *(*source)->polar();
  double modelTop = -1.0, rasterTop = -1.0, modelMax = -1e9, rasterMax = -1e9, tolerance = 0.0;
  const auto& geod = GeographicLib::Geodesic::WGS84();
  for (int i = 0; i < raster->columns; ++i) {
    for (int j = 0; j < raster->rows; ++j) {
      const globe::Geodetic p = geometry->geodeticAt(i + 0.5, j + 0.5);
      const double heightMsl = p.heightMeters - geoid->undulationMeters(p.latDeg, p.lonDeg);
      double s12 = 0, azi1 = 0, azi2 = 0;
      geod.Inverse(o.siteLatDeg, o.siteLonDeg, p.latDeg, p.lonDeg, s12, azi1, azi2);
      const double model = volume::syntheticStormDbz(o, s12 * std::sin(azi1 * M_PI / 180.0),
                                                     s12 * std::cos(azi1 * M_PI / 180.0), heightMsl);
      const float v = raster->at(i, j);
      if (model >= 20.0 && heightMsl > modelTop) {
        modelTop = heightMsl;
        // The radar's vertical resolution at this point: the gap between the sweeps around its
        // elevation plus one beam width, at its range (elevations are sorted).
        const volume::AntennaCoordinates ac =
            volume::antennaCoordinatesExact(polar.site, polar.beam, globe::geodeticToEcef(p));
        double gapDeg = polar.sweeps.back().elevationDeg - polar.sweeps.front().elevationDeg;
        for (std::size_t k = 0; k + 1 < polar.sweeps.size(); ++k)
          if (polar.sweeps[k].elevationDeg <= ac.elevationDeg && ac.elevationDeg < polar.sweeps[k + 1].elevationDeg)
            gapDeg = polar.sweeps[k + 1].elevationDeg - polar.sweeps[k].elevationDeg;
        tolerance = ac.rangeMeters * (gapDeg + polar.beamWidthDeg) * M_PI / 180.0;
      }
      if (std::isfinite(v) && v >= 20.0f) rasterTop = std::max(rasterTop, heightMsl);
      if (std::isfinite(model)) modelMax = std::max(modelMax, model);
      if (std::isfinite(v)) rasterMax = std::max(rasterMax, double(v));
    }
  }
  std::cout << "20 dBZ echo top: model " << modelTop << " m, slice " << rasterTop << " m (tolerance " << tolerance
            << " m); peak: model " << modelMax << " dBZ, slice " << rasterMax << " dBZ\n";
  ASSERT_GT(modelTop, 5000.0);  // a deep storm along this path
  EXPECT_NEAR(rasterTop, modelTop, tolerance);
  // The peak: the model varies by up to ~0.6 dB per km near the core (22 dB over 6 km, squared)
  // horizontally and a few dB between sweeps 1.5 km apart vertically at 60 km; linear
  // interpolation never overshoots, so the slice's peak is at most the model's (+ 0.005 dB of
  // 0.01 dB storage) and within 4 dB below it.
  EXPECT_LE(rasterMax, modelMax + 0.01);
  EXPECT_GT(rasterMax, modelMax - 4.0);
}

// The grid source: the synthetic grid's time, name, SYNTHETIC mark and extent; an unknown
// variable and a CAPPI above the grid are refused with messages naming the file.
TEST(Slice, GridSourceAndBadRequests) {
  const std::string path = ATMOGLOBE_TEST_OUTPUT_DIR + "/slice_grid.nc";
  volume::SyntheticGridOptions go;
  go.nx = 60;
  go.ny = 50;
  go.levels = 12;
  go.times = 4;
  ASSERT_TRUE(volume::writeSyntheticGrid(path, go).ok());
  volume::SliceSourceOptions load;
  load.kind = volume::SliceSourceOptions::Kind::Grid;
  load.path = path;
  load.time = "2020-05-01T20:00:00Z";
  auto source = volume::SliceSource::load(load);
  ASSERT_TRUE(source) << source.error();
  EXPECT_TRUE((*source)->synthetic());
  EXPECT_EQ((*source)->validTime(), "2020-05-01T20:00:00Z");
  EXPECT_EQ((*source)->field().name, "dbz");
  EXPECT_EQ((*source)->field().units, "dBZ");
  const volume::LatLonBox e = (*source)->extent();
  EXPECT_LT(e.southDeg, go.centerLatDeg);
  EXPECT_GT(e.northDeg, go.centerLatDeg);
  EXPECT_LT(e.westDeg, go.centerLonDeg);
  EXPECT_GT(e.eastDeg, go.centerLonDeg);

  volume::SliceRequest request;
  request.heightMeters = 40000.0;
  auto tooHigh = volume::sliceGeometryFor(**source, request);
  ASSERT_FALSE(tooHigh);
  EXPECT_NE(tooHigh.error().find("outside the volume"), std::string::npos) << tooHigh.error();
  EXPECT_NE(tooHigh.error().find(path), std::string::npos) << tooHigh.error();
  // A box beside the grid: nothing to show.
  request.heightMeters = 3000.0;
  request.box = volume::LatLonBox{10.0, 11.0, 10.0, 11.0};
  request.columns = request.rows = 8;
  auto geometry = volume::sliceGeometryFor(**source, request);
  ASSERT_TRUE(geometry) << geometry.error();
  auto raster = volume::sampleSource(**source, *geometry);
  ASSERT_FALSE(raster);
  EXPECT_NE(raster.error().find("no data on the CAPPI"), std::string::npos) << raster.error();

  load.field = "no_such_variable";
  auto unknown = volume::SliceSource::load(load);
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().find("no_such_variable"), std::string::npos) << unknown.error();
  EXPECT_NE(unknown.error().find(path), std::string::npos) << unknown.error();
}

TEST(Slice, BadPathsAndBoxesAreRefused) {
  auto one = volume::GeodesicPath::create({{35.0, -97.0}});
  ASSERT_FALSE(one);
  EXPECT_NE(one.error().find("at least two points"), std::string::npos) << one.error();
  auto same = volume::GeodesicPath::create({{35.0, -97.0}, {35.0, -97.0}});
  ASSERT_FALSE(same);
  EXPECT_NE(same.error().find("less than 1 m apart"), std::string::npos) << same.error();
  auto antipodal = volume::GeodesicPath::create({{10.0, 20.0}, {-10.0, -160.0}});
  ASSERT_FALSE(antipodal);
  EXPECT_NE(antipodal.error().find("antipodal"), std::string::npos) << antipodal.error();
  auto badLat = volume::GeodesicPath::create({{95.0, 0.0}, {35.0, -97.0}});
  ASSERT_FALSE(badLat);
  EXPECT_NE(badLat.error().find("path point 1"), std::string::npos) << badLat.error();

  auto parsed = volume::parsePathText("35.1,-97.2; 36,-96");
  ASSERT_TRUE(parsed) << parsed.error();
  ASSERT_EQ(parsed->size(), 2u);
  EXPECT_EQ((*parsed)[1].lonDeg, -96.0);
  auto onePoint = volume::parsePathText("35,-97");
  ASSERT_FALSE(onePoint);
  EXPECT_NE(onePoint.error().find("at least two points"), std::string::npos) << onePoint.error();
  auto notNumber = volume::parsePathText("35,-97;abc,1");
  ASSERT_FALSE(notNumber);
  EXPECT_NE(notNumber.error().find("path point 2"), std::string::npos) << notNumber.error();
  EXPECT_FALSE(volume::parsePathText("35,-97,100;36,-96"));

  auto box = volume::parseBoxText("30,40,170,-170");  // across the antimeridian
  ASSERT_TRUE(box) << box.error();
  EXPECT_EQ(box->eastDeg, 190.0);
  EXPECT_FALSE(volume::parseBoxText("40,30,0,10"));  // south > north
  EXPECT_FALSE(volume::parseBoxText("30,40,0"));

  volume::CrossSectionSpec spec;
  spec.points = {{35.0, -97.0}, {36.0, -96.0}};
  spec.bottomMeters = 5000.0;
  spec.topMeters = 1000.0;
  spec.datum = volume::SliceHeightDatum::Ellipsoid;
  EXPECT_FALSE(SliceGeometry::crossSection(spec, nullptr));
  spec.bottomMeters = 0.0;
  spec.datum = volume::SliceHeightDatum::SeaLevel;
  auto noGeoid = SliceGeometry::crossSection(spec, nullptr);
  ASSERT_FALSE(noGeoid);
  EXPECT_NE(noGeoid.error().find("geoid"), std::string::npos);
  volume::CappiSpec cappi;
  cappi.box = {30.0, 40.0, 0.0, 10.0};
  cappi.datum = volume::SliceHeightDatum::Ellipsoid;
  cappi.columns = 0;
  EXPECT_FALSE(SliceGeometry::cappi(cappi, nullptr));
}
