// Units, the standard atmosphere and geopotential -> geometric height, against published tables.
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace atmoglobe::volume;

TEST(VerticalCoordinate, StandardAtmosphereMatchesTheUsStandardAtmosphere1976Table) {
  // U.S. Standard Atmosphere 1976 (NOAA/NASA/USAF), table of layer bases (geopotential height
  // in m', pressure in Pa, 6 significant digits as published). Relative tolerance 1e-5: half a
  // unit in the 6th digit is 5e-6; above 47 km the published bases differ from ours by up to
  // 7e-6 (rounding carried through the layers below), i.e. 0.06 m of height.
  struct Row {
    double h, p;
  };
  const Row table[] = {{0.0, 101325.0},    {11000.0, 22632.1}, {20000.0, 5474.89}, {32000.0, 868.019},
                       {47000.0, 110.906}, {51000.0, 66.9389}, {71000.0, 3.95642}};
  for (const Row& r : table) {
    EXPECT_NEAR(standardAtmospherePressurePa(r.h), r.p, 1e-5 * r.p) << "H = " << r.h;
    // Inverse: the height of the tabulated pressure, within what that tolerance on p allows
    // (dH = H_scale dp/p, H_scale <= 8.5 km: 1e-5 * 8.5 km = 0.085 m).
    EXPECT_NEAR(standardAtmosphereGeopotentialHeightMeters(r.p), r.h, 0.085) << "p = " << r.p;
  }
}

TEST(VerticalCoordinate, StandardAtmosphereAgreesWithTheTroposphereFormulaOfTheReference) {
  // REFERENCE.md section 4: z = 44331.5 - 4946.62 p^0.190263 (p in Pa), the ISA troposphere
  // with rounded constants; it should agree with ours to about a metre below 11 km.
  for (double p = 101325.0; p >= 22700.0; p -= 2500.0) {
    const double z = 44331.5 - 4946.62 * std::pow(p, 0.190263);
    EXPECT_NEAR(standardAtmosphereGeopotentialHeightMeters(p), z, 1.5) << "p = " << p;
  }
}

TEST(VerticalCoordinate, StandardAtmosphereRoundTripsAndExtendsBeyondItsLayers) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> h(-1000.0, 84000.0);
  for (int i = 0; i < 2000; ++i) {
    const double z = h(rng);
    const double p = standardAtmospherePressurePa(z);
    ASSERT_GT(p, 0.0);
    ASSERT_NEAR(standardAtmosphereGeopotentialHeightMeters(p), z, 1e-6 * (1.0 + std::fabs(z))) << z;
  }
  // 1050 hPa lies below sea level; 0.1 Pa above the last layer: both finite and ordered.
  EXPECT_LT(standardAtmosphereGeopotentialHeightMeters(105000.0), 0.0);
  EXPECT_GT(standardAtmosphereGeopotentialHeightMeters(0.1), 84000.0);
}

TEST(VerticalCoordinate, NormalGravityMatchesTr8350) {
  // NIMA TR8350.2 (3rd ed.) table 3.4: equatorial and polar normal gravity of WGS84.
  EXPECT_NEAR(normalGravity(0.0), 9.7803253359, 1e-10);
  EXPECT_NEAR(normalGravity(90.0), 9.8321849378, 1e-9);
  EXPECT_NEAR(normalGravity(-90.0), 9.8321849378, 1e-9);
}

TEST(VerticalCoordinate, GeometricHeightMatchesTheUsStandardAtmosphereRelation) {
  // USSA 1976 defines geometric Z from geopotential H with r0 = 6356766 m at the latitude where
  // sea-level gravity equals g0 (45.5425 deg): Z = r0 H / (r0 - H). Our normal-gravity model at
  // that latitude has gamma within 1e-5 of g0 and an effective radius 1/c1 within 0.01% of r0,
  // so the two agree to ~1e-5 H (0.1 m at 10 km) plus 1e-4 of Z - H (0.03 m at 30 km).
  constexpr double kR0 = 6356766.0;
  for (double h : {0.0, 1000.0, 5000.0, 10000.0, 20000.0, 30000.0, 50000.0}) {
    const double ussa = kR0 * h / (kR0 - h);
    EXPECT_NEAR(geometricFromGeopotentialHeightMeters(h, 45.5425), ussa, 1e-5 * h + 0.01) << "H = " << h;
  }
  // At the equator gravity is weaker (9.7803 against g0): a geopotential metre is longer by
  // g0 / gamma - 1 = 2.7e-3, so 10 km' lies 27 m + the 1/r^2 term (15.7 m) above 10 km.
  const double z = geometricFromGeopotentialHeightMeters(10000.0, 0.0);
  EXPECT_NEAR(z - 10000.0, 27.0 + 15.7, 0.5);
  // At the poles gravity is stronger: the layer is thinner (-2.6e-3: -26 m + 15.7 m).
  EXPECT_NEAR(geometricFromGeopotentialHeightMeters(10000.0, 90.0) - 10000.0, -26.2 + 15.7, 0.5);
  // The converter class is the same function.
  const GeopotentialToGeometric conv(33.3);
  EXPECT_EQ(conv(12345.0), geometricFromGeopotentialHeightMeters(12345.0, 33.3));
}

TEST(VerticalCoordinate, Units) {
  EXPECT_EQ(pressureUnitToPascal("Pa"), 1.0);
  EXPECT_EQ(pressureUnitToPascal("hPa"), 100.0);
  EXPECT_EQ(pressureUnitToPascal("millibars"), 100.0);
  EXPECT_EQ(pressureUnitToPascal("mb"), 100.0);
  EXPECT_EQ(pressureUnitToPascal("kPa"), 1000.0);
  EXPECT_FALSE(pressureUnitToPascal("PA")) << "SI symbols are case-sensitive";
  EXPECT_FALSE(pressureUnitToPascal("m"));
  EXPECT_EQ(lengthUnitToMeters("m"), 1.0);
  EXPECT_EQ(lengthUnitToMeters("metres"), 1.0);
  EXPECT_EQ(lengthUnitToMeters("km"), 1000.0);
  EXPECT_EQ(lengthUnitToMeters("ft"), 0.3048);
  EXPECT_FALSE(lengthUnitToMeters("gpm")) << "geopotential metres are not lengths";
  EXPECT_EQ(geopotentialHeightUnitToMeters("gpm"), 1.0);
  EXPECT_EQ(geopotentialHeightUnitToMeters("gpdm"), 10.0);
  for (const char* u : {"m2 s-2", "m**2 s**-2", "m^2/s^2", "m2/s2", "J kg-1"}) EXPECT_TRUE(isGeopotentialUnit(u)) << u;
  EXPECT_FALSE(isGeopotentialUnit("m"));
}

TEST(VerticalCoordinate, UnitsThroughUdunits) {
  EXPECT_TRUE(unitDatabaseProblem().empty()) << unitDatabaseProblem();
  // Spellings no list held: prefixes, plurals, names, powers, blanks around.
  EXPECT_EQ(pressureUnitToPascal("hectopascals"), 100.0);
  EXPECT_EQ(pressureUnitToPascal("mbar"), 100.0);
  EXPECT_EQ(pressureUnitToPascal("bar"), 1.0e5);
  EXPECT_EQ(pressureUnitToPascal(" hPa "), 100.0);
  EXPECT_EQ(pressureUnitToPascal("100 Pa"), 100.0);
  EXPECT_EQ(lengthUnitToMeters("kilometres"), 1000.0);
  EXPECT_EQ(lengthUnitToMeters("Meters"), 1.0);
  EXPECT_DOUBLE_EQ(*lengthUnitToMeters("mm"), 1.0e-3);
  EXPECT_EQ(lengthUnitToMeters("feet"), 0.3048);
  EXPECT_EQ(geopotentialUnitToSi("J/kg"), 1.0);
  EXPECT_EQ(geopotentialUnitToSi("m**2/s**2"), 1.0);
  EXPECT_DOUBLE_EQ(*geopotentialUnitToSi("km2 s-2"), 1.0e6);
  // Neither pressure, length nor geopotential: not units, another quantity, or an offset scale.
  for (const char* u : {"", "level", "1", "hybrid_sigma_pressure", "K", "degC", "m s-1", "degrees_north", "sigma"}) {
    EXPECT_FALSE(pressureUnitToPascal(u)) << u;
    EXPECT_FALSE(lengthUnitToMeters(u)) << u;
    EXPECT_FALSE(geopotentialUnitToSi(u)) << u;
  }
  EXPECT_FALSE(lengthUnitToMeters("Pa"));
  EXPECT_FALSE(pressureUnitToPascal("J kg-1"));
}
