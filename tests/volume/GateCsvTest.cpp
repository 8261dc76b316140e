// `atmoglobe gates` rows at full precision: recomputing a gate's position from the row's own
// azimuth, elevation and range lands within 1 mm of the row's ECEF coordinates, at sites from
// the equator to the poles and across the antimeridian, out to 460 km.
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/GateCsv.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace atmoglobe;

std::vector<std::string> splitRow(const std::string& row) {
  std::vector<std::string> f;
  std::stringstream in(row);
  for (std::string cell; std::getline(in, cell, ',');) f.push_back(cell);
  if (!row.empty() && row.back() == ',') f.push_back("");
  return f;
}

double number(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

}  // namespace

TEST(GateCsv, RowsRecomputeToWithinOneMillimetre) {
  EXPECT_EQ(std::string(volume::gateCsvHeader()),
            "sweep,ray,gate,azimuth_deg,elevation_deg,range_m,lat_deg,lon_deg,height_m,ecef_x,ecef_y,ecef_z,value\n");
  const volume::BeamModel model;
  const volume::GeolocationSite sites[] = {
      {33.654, -101.814, 1029.0}, {0.0, 179.999, 10.0}, {89.9, 45.0, 100.0}, {-89.5, -170.0, 2800.0}};
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> az(0.0f, 360.0f), el(-0.5f, 30.0f);
  double worstMm = 0.0, worstFourDecimalsMm = 0.0;
  for (const volume::GeolocationSite& site : sites) {
    for (int k = 0; k < 200; ++k) {
      // Angles as readers store them (float), the largest near 360 deg where a float's step is
      // 3e-5 deg; ranges to 460 km.
      const float azimuthDeg = k == 0 ? 359.99997f : az(rng);
      const float elevationDeg = k == 1 ? 0.0f : el(rng);
      const double rangeMeters = 2125.0 + 250.0 * (k * 7 % 1832);
      const volume::GatePosition p = volume::geolocateGateExact(site, model, azimuthDeg, elevationDeg, rangeMeters);
      const float value = 42.5f;
      std::string row;
      volume::appendGateCsvRow(row, 3, static_cast<std::size_t>(k), 17, azimuthDeg, elevationDeg, rangeMeters, p,
                               &value);
      ASSERT_EQ(row.back(), '\n');
      row.pop_back();
      const std::vector<std::string> f = splitRow(row);
      ASSERT_EQ(f.size(), 13u) << row;
      EXPECT_EQ(f[0], "3");
      EXPECT_EQ(f[2], "17");
      EXPECT_EQ(f[12], "42.5");
      const volume::GatePosition again =
          volume::geolocateGateExact(site, model, number(f[3]), number(f[4]), number(f[5]));
      const glm::dvec3 rowEcef(number(f[9]), number(f[10]), number(f[11]));
      const double mm = glm::length(again.ecef - rowEcef) * 1000.0;
      worstMm = std::max(worstMm, mm);
      EXPECT_LE(mm, 1.0) << row;
      // The row's latitude, longitude and height give the same point too.
      const glm::dvec3 fromGeodetic = globe::geodeticToEcef({number(f[6]), number(f[7]), number(f[8])});
      EXPECT_LE(glm::length(fromGeodetic - rowEcef) * 1000.0, 1.0) << row;
      // The bound is not loose: with 4 decimals in the angles (the old format) rows at long
      // range miss by decimetres.
      const volume::GatePosition rounded = volume::geolocateGateExact(
          site, model, std::round(azimuthDeg * 1e4) / 1e4, std::round(elevationDeg * 1e4) / 1e4, rangeMeters);
      worstFourDecimalsMm = std::max(worstFourDecimalsMm, glm::length(rounded.ecef - p.ecef) * 1000.0);
    }
  }
  std::cout << "gates rows: worst recomputation error " << worstMm << " mm (4-decimal angles: " << worstFourDecimalsMm
            << " mm)\n";
  EXPECT_GT(worstFourDecimalsMm, 10.0);
}

TEST(GateCsv, NoDataIsEmptyAndNoEchoIsMinusInfinity) {
  const volume::GatePosition p;
  std::string row;
  const float noData = volume::kNoData, noEcho = volume::kNoEcho;
  volume::appendGateCsvRow(row, 0, 0, 0, 1.0, 0.5, 2125.0, p, &noData);
  volume::appendGateCsvRow(row, 0, 0, 1, 1.0, 0.5, 2375.0, p, &noEcho);
  volume::appendGateCsvRow(row, 0, 0, 2, 1.0, 0.5, 2625.0, p, nullptr);
  std::stringstream in(row);
  std::string a, b, c;
  std::getline(in, a);
  std::getline(in, b);
  std::getline(in, c);
  EXPECT_EQ(a.back(), ',');
  EXPECT_EQ(b.substr(b.size() - 5), ",-inf");
  EXPECT_EQ(c.back(), ',');
}
