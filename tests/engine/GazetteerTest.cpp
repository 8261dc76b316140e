// Fly-to names (engine/Gazetteer.h): scene entries, a station list, tzdata's zone1970.tab, LAT,LON.
#include <atmoglobe/engine/Gazetteer.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace atmoglobe;
using engine::Gazetteer;
using engine::Place;

namespace {
Place place(std::string name, std::string kind, double lat, double lon) {
  Place p;
  p.names = {std::move(name)};
  p.kind = std::move(kind);
  p.latDeg = lat;
  p.lonDeg = lon;
  return p;
}
}  // namespace

TEST(Gazetteer, NamesMatchExactlyThenByPrefixThenBySubstring) {
  Gazetteer g;
  g.add(place("KTLX", "radar", 35.33, -97.28));
  g.add(place("Norman storm", "marker", 35.2, -97.4));
  g.add(place("Stormy Point", "marker", 1.0, 2.0));
  // Case and '_' do not matter; exact beats prefix beats substring, whatever the order.
  EXPECT_EQ(g.find("ktlx")->names[0], "KTLX");
  EXPECT_EQ(g.find("storm")->names[0], "Stormy Point");  // prefix, though "Norman storm" comes first
  EXPECT_EQ(g.find("man_st")->names[0], "Norman storm");
  const auto missing = g.find("Atlantis");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("'Atlantis'"), std::string::npos) << missing.error();
  EXPECT_FALSE(g.find("   "));
}

TEST(Gazetteer, LatLonIsAPlaceAndIsChecked) {
  Gazetteer g;
  const auto p = g.find(" 35.5, -97.25 ");
  ASSERT_TRUE(p) << p.error();
  EXPECT_EQ(p->latDeg, 35.5);
  EXPECT_EQ(p->lonDeg, -97.25);
  const auto withHeight = g.find("10,350,2000");
  ASSERT_TRUE(withHeight) << withHeight.error();
  EXPECT_EQ(withHeight->lonDeg, -10.0);  // wrapped to [-180, 180]
  EXPECT_EQ(withHeight->viewHeightMeters, 2000.0);
  const auto bad = g.find("95,10");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("latitude"), std::string::npos) << bad.error();
  EXPECT_FALSE(g.find("10,20,0"));  // height below 1 m
}

TEST(Gazetteer, ZoneTabCitiesWithMinutesAndSeconds) {
  Gazetteer g;
  // Lines as zone1970.tab writes them (DDMM and DDMMSS forms); coordinates from the file.
  ASSERT_TRUE(
      g.addZoneTabText("# comment\nFR,MC\t+4852+00220\tEurope/Paris\n"
                       "US\t+415100-0873900\tAmerica/Chicago\tCentral (most areas)\n"
                       "BR\t-2332-04637\tAmerica/Sao_Paulo\tBrazil\n",
                       "test.tab", 1e5));
  const auto paris = g.find("paris");
  ASSERT_TRUE(paris);
  EXPECT_NEAR(paris->latDeg, 48.0 + 52.0 / 60.0, 1e-12);
  EXPECT_NEAR(paris->lonDeg, 2.0 + 20.0 / 60.0, 1e-12);
  const auto chicago = g.find("America/Chicago");
  ASSERT_TRUE(chicago);
  EXPECT_NEAR(chicago->latDeg, 41.85, 1e-12);
  EXPECT_NEAR(chicago->lonDeg, -87.65, 1e-12);
  const auto saoPaulo = g.find("Sao Paulo");
  ASSERT_TRUE(saoPaulo);
  EXPECT_NEAR(saoPaulo->latDeg, -(23.0 + 32.0 / 60.0), 1e-12);
  EXPECT_EQ(saoPaulo->viewHeightMeters, 1e5);
  const auto bad = g.addZoneTabText("FR\t4852+00220\tEurope/Paris\n", "bad.tab", 1e5);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("bad.tab line 1"), std::string::npos) << bad.error();
}

TEST(Gazetteer, TheMachinesZoneTabHasTheWorldsCities) {
  // Debian tzdata (scripts/install-deps.sh) ships it; a machine without it skips.
  if (!std::filesystem::exists(engine::kZoneTabPath)) GTEST_SKIP() << "no " << engine::kZoneTabPath;
  Gazetteer g;
  ASSERT_TRUE(g.addZoneTab(engine::kZoneTabPath, 1e5));
  EXPECT_GT(g.size(), 300u);  // zone1970.tab has ~310 zones
  const auto tokyo = g.find("Tokyo");
  ASSERT_TRUE(tokyo);
  EXPECT_NEAR(tokyo->latDeg, 35.65, 0.1);  // the file's +353916+1394441
  EXPECT_NEAR(tokyo->lonDeg, 139.74, 0.1);
}

TEST(Gazetteer, StationListsByIdAndTheSceneFirst) {
  const std::string dir = atmoglobe_test::freshTestDir("gazetteer");
  const std::string path = dir + "/sites.csv";
  std::ofstream(path) << "id,lat,lon,name\nKTLX,35.3331,-97.2778,Oklahoma City\nKFWS,32.573,-97.303,Dallas\n";
  Gazetteer g;
  g.add(place("KTLX", "radar", 35.0, -97.0));  // the scene's, added first
  ASSERT_TRUE(g.addStationList(path, "NEXRAD site", 4e5));
  EXPECT_EQ(g.find("KTLX")->kind, "radar");
  const auto fws = g.find("kfws");
  ASSERT_TRUE(fws);
  EXPECT_EQ(fws->kind, "NEXRAD site");
  EXPECT_EQ(fws->latDeg, 32.573);
  EXPECT_EQ(g.find("dallas")->names[0], "KFWS");
  const engine::CameraPose v = engine::viewOfPlace(*fws);
  EXPECT_EQ(v.heightMeters, 4e5);
  EXPECT_EQ(v.pitchDeg, -90.0);
  EXPECT_FALSE(g.addStationList(dir + "/none.csv", "x", 1.0));
}
