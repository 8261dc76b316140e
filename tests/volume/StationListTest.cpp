// Station lists: the real OURadar NEXRAD site file, CSV and JSON written here, and bad files.
//
// References:
//  - The OURadar file (nexrad-locations.json of github.com/OURadar/radar-data) holds 158 WSR-88D
//    sites; KLBB is at 33.6541 N 101.8142 W (from the Level II file: see the tolerance note in the
//    test).
//  - python3 -c "import json; d=json.load(open('OURadar_nexrad-locations.json')); print(len(d),
//    list(d)[0], list(d)[-1], d['KLBB'], d['KTLX'])" prints 158 KABR KYUX,
//    KLBB {latitude 33.65416666666667, longitude -101.81416666666667, elevation 993.3432,
//    height 20.0}, KTLX {35.33305555555556, -97.27777777777777, 369.7224, 15.0}.
#include <atmoglobe/volume/StationList.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

namespace atmoglobe::volume {
namespace {

namespace fs = std::filesystem;

const std::string kOuRadar = atmoglobe_test::testDataPath("stations/OURadar_nexrad-locations.json");

std::string writeFile(const std::string& name, const std::string& text) {
  const fs::path dir = fs::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "stations";
  fs::create_directories(dir);
  const std::string p = (dir / name).string();
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::vector<Station> mustRead(const std::string& path) {
  auto r = readStationList(path);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error());
  if (!r.ok()) return {};
  return std::move(r).value();
}

const Station* find(const std::vector<Station>& v, const std::string& id) {
  auto it = std::find_if(v.begin(), v.end(), [&](const Station& s) { return s.id == id; });
  return it == v.end() ? nullptr : &*it;
}

// Expects an error containing every one of `parts`.
void expectError(const std::string& text, const std::string& fileName, std::initializer_list<const char*> parts) {
  const std::string path = writeFile(fileName, text);
  auto r = readStationList(path);
  ASSERT_FALSE(r.ok()) << fileName << " was accepted";
  EXPECT_NE(r.error().find(path), std::string::npos) << r.error();
  for (const char* p : parts) EXPECT_NE(r.error().find(p), std::string::npos) << "'" << p << "' not in: " << r.error();
}

TEST(StationList, OuRadarNexradSites) {
  SKIP_WITHOUT_TEST_DATA(kOuRadar);
  const auto v = mustRead(kOuRadar);
  ASSERT_EQ(v.size(), 158u);
  EXPECT_EQ(v.front().id, "KABR");  // file order kept
  EXPECT_EQ(v.back().id, "KYUX");
  const Station* lbb = find(v, "KLBB");
  ASSERT_NE(lbb, nullptr);
  // README: 33.6541 N 101.8142 W describes the KLBB Level II file's own site record, a second
  // source (the JSON says 33.654167, -101.814167: 7e-5 and 3e-5 deg away, i.e. the README
  // truncates or the sources differ by < 8 m). 1e-4 deg (11 m) accepts that; a wrong field,
  // sign or swapped axes would be off by degrees.
  EXPECT_NEAR(lbb->latDeg, 33.6541, 1e-4);
  EXPECT_NEAR(lbb->lonDeg, -101.8142, 1e-4);
  // python3 json (see the top): the exact doubles; only a parse slip could differ.
  EXPECT_DOUBLE_EQ(lbb->latDeg, 33.65416666666667);
  EXPECT_DOUBLE_EQ(lbb->elevationMeters, 993.3432);  // ground elevation ("elevation"), not + tower
  EXPECT_TRUE(lbb->hasElevation);
  ASSERT_TRUE(lbb->towerHeightMeters.has_value());
  EXPECT_DOUBLE_EQ(*lbb->towerHeightMeters, 20.0);  // "height" is the tower when "elevation" exists
  const Station* tlx = find(v, "KTLX");
  ASSERT_NE(tlx, nullptr);
  EXPECT_DOUBLE_EQ(tlx->lonDeg, -97.27777777777777);
  EXPECT_DOUBLE_EQ(tlx->elevationMeters + *tlx->towerHeightMeters, 369.7224 + 15.0);
  for (const Station& s : v) {
    EXPECT_EQ(s.id.size(), 4u) << s.id;  // ICAO ids
    EXPECT_TRUE(s.towerHeightMeters.has_value()) << s.id;
  }
}

TEST(StationList, CsvWithHeaderAnyOrderQuotesAndComments) {
  const std::string text =
      "\xEF\xBB\xBF# radar sites\r\n"
      " Name , ICAO,Longitude,Latitude,Elevation_m,extra\r\n"
      "\"Oklahoma City, OK\",KTLX,-97.2778,35.3331,369.7,x\r\n"
      "\r\n"
      "\"Lubbock \"\"West\"\" TX\", KLBB , -101.8142 , +33.6541 ,993.3,\"y\"\r\n"
      "Nowhere,XNOE,190,0,,z\r\n";
  const auto v = mustRead(writeFile("good.csv", text));
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].id, "KTLX");
  EXPECT_EQ(v[0].name, "Oklahoma City, OK");
  EXPECT_DOUBLE_EQ(v[0].latDeg, 35.3331);
  EXPECT_DOUBLE_EQ(v[0].lonDeg, -97.2778);
  EXPECT_DOUBLE_EQ(v[0].elevationMeters, 369.7);
  EXPECT_FALSE(v[0].towerHeightMeters.has_value());
  EXPECT_EQ(v[1].id, "KLBB");
  EXPECT_EQ(v[1].name, "Lubbock \"West\" TX");
  EXPECT_DOUBLE_EQ(v[1].latDeg, 33.6541);
  EXPECT_DOUBLE_EQ(v[1].elevationMeters, 993.3);
  // Empty elevation cell: unknown, 0; longitude 190 -> -170.
  EXPECT_FALSE(v[2].hasElevation);
  EXPECT_EQ(v[2].elevationMeters, 0.0);
  EXPECT_DOUBLE_EQ(v[2].lonDeg, -170.0);
}

TEST(StationList, CsvMinimalColumnsAndHeightAsElevation) {
  auto v = mustRead(writeFile("minimal.csv", "station,lat,long\nA,1,2\nB,-90,-180\n"));
  ASSERT_EQ(v.size(), 2u);
  EXPECT_FALSE(v[0].hasElevation);
  EXPECT_EQ(v[1].latDeg, -90.0);
  EXPECT_EQ(v[1].lonDeg, 180.0);  // -180 and 180 are one meridian: reported as 180
  // `height` alone is the elevation; with `elevation` beside it, it is the tower height.
  v = mustRead(writeFile("height.csv", "id,lat,lon,height\nA,1,2,150\n"));
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].elevationMeters, 150.0);
  EXPECT_FALSE(v[0].towerHeightMeters.has_value());
  v = mustRead(writeFile("height2.csv", "id,lat,lon,height,elevation\nA,1,2,30,150\n"));
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].elevationMeters, 150.0);
  EXPECT_EQ(v[0].towerHeightMeters.value_or(-1), 30.0);
  v = mustRead(writeFile("header-only.csv", "id,lat,lon\n"));
  EXPECT_TRUE(v.empty());
}

TEST(StationList, JsonArrayAndObjectForms) {
  auto v = mustRead(writeFile("array.json",
                              R"([{"id": "KTLX", "lat": 35.3331, "lon": -97.2778, "elevation": 369.7, "name": "OKC"},
                                  {"icao": "KLBB", "latitude": "33.6541", "longitude": -101.8142},
                                  {"station": 42, "lat": 0, "lon": 0, "altitude": -20}])"));
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].id, "KTLX");
  EXPECT_EQ(v[0].name, "OKC");
  EXPECT_DOUBLE_EQ(v[0].elevationMeters, 369.7);
  EXPECT_EQ(v[1].id, "KLBB");
  EXPECT_DOUBLE_EQ(v[1].latDeg, 33.6541);  // numeric string accepted
  EXPECT_FALSE(v[1].hasElevation);
  EXPECT_EQ(v[2].id, "42");
  EXPECT_EQ(v[2].elevationMeters, -20.0);
  // Object form: the key is the id; key order is file order (not sorted).
  v = mustRead(
      writeFile("object.json", R"({"ZZZZ": {"lat": 1, "lon": 2}, "AAAA": {"lat": 3, "lon": 4, "tower_height": 12}})"));
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].id, "ZZZZ");
  EXPECT_EQ(v[1].id, "AAAA");
  EXPECT_EQ(v[1].towerHeightMeters.value_or(-1), 12.0);
  EXPECT_TRUE(mustRead(writeFile("empty-array.json", "  []")).empty());
}

TEST(StationList, BadCsvFilesNameLineAndReason) {
  expectError("id,lat,lon\nA,95,0\n", "lat95.csv", {"line 2", "bad latitude 95"});
  expectError("id,lat,lon\nA,1,2\n\nB,10,-400\n", "lon.csv", {"line 4", "bad longitude -400"});
  expectError("id,lon,elevation\nA,1,2\n", "nolat.csv", {"line 1", "latitude"});
  expectError("name,value\nx,1\n", "nocols.csv", {"line 1", "id", "latitude", "longitude"});
  expectError("id,lat,lon\nA,abc,2\n", "nan.csv", {"line 2", "latitude 'abc' is not a number"});
  expectError("id,lat,lon\nA,1.5x,2\n", "trail.csv", {"line 2", "'1.5x'"});
  expectError("id,lat,lon\nA,nan,2\n", "nanword.csv", {"line 2", "not a number"});
  expectError("id,lat,lon\nA,1\n", "short.csv", {"line 2", "fields"});
  expectError("id,lat,lon\n\"A,1,2\n", "quote.csv", {"line 2", "unterminated"});
  expectError("id,lat,lon,elev\nA,1,2,12000\n", "elev.csv", {"line 2", "bad elevation 12000"});
  expectError("id,lat,lat,lon\nA,1,2,3\n", "twice.csv", {"line 1", "two columns"});
  expectError("id,lat,lon\n,1,2\n", "noid.csv", {"line 2", "empty id"});
  expectError("   \n\n", "blank.csv", {"empty"});
}

TEST(StationList, BadJsonFilesNameEntryAndReason) {
  expectError(R"({"KAAA": {"latitude": 95, "longitude": 0}})", "lat95.json", {"entry 'KAAA'", "bad latitude 95"});
  expectError(R"([{"id": "A", "lat": 1, "lon": 2}, {"id": "B", "lat": 1}])", "nolon.json",
              {"entry 1 ('B')", "no longitude"});
  expectError(R"([{"lat": 1, "lon": 2}])", "noid.json", {"entry 0", "no id"});
  expectError(R"([{"id": "A", "lat": "north", "lon": 2}])", "text.json",
              {"entry 0", "latitude \"north\" is not a number"});
  expectError(R"({"KAAA": {"lat": 1, "lon": 2, "elevation": [1]}})", "arr.json", {"entry 'KAAA'", "elevation"});
  expectError(R"({"KAAA": 5})", "notobj.json", {"entry 'KAAA'", "not an object"});
  expectError(R"([{"id": "A", "lat": 1, "lon": 2}, )", "trunc.json", {"not valid JSON", "line 1"});
  expectError(R"({"KAAA": {"lat": 1, "lon": 2, "height": 20, "elevation": 100, "tower": -5}})", "tower.json",
              {"entry 'KAAA'", "bad tower height -5"});
}

TEST(StationList, UnreadablePaths) {
  auto r = readStationList("/nonexistent/stations.csv");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("/nonexistent/stations.csv"), std::string::npos);
  EXPECT_NE(r.error().find("No such file"), std::string::npos) << r.error();
  const fs::path dir = fs::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "stations" / "a-directory";
  fs::create_directories(dir);
  r = readStationList(dir.string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find(dir.string()), std::string::npos) << r.error();
}

}  // namespace
}  // namespace atmoglobe::volume

namespace atmoglobe::volume {
namespace {

TEST(StationList, BuiltinNexradTableHoldsEveryWsr88dSite) {
  const std::vector<Station>& sites = builtinNexradSites();
  // 159 rows: the NOAA list's 147 sites (contiguous US, Hawaii, Puerto Rico, the Azores), 7 in
  // Alaska, Guam, 3 at bases in Korea and Okinawa, and KDGX.
  ASSERT_EQ(sites.size(), 159u);
  std::set<std::string> ids;
  for (const Station& s : sites) {
    EXPECT_EQ(s.id.size(), 4u) << s.id;
    EXPECT_TRUE(ids.insert(s.id).second) << "duplicate " << s.id;
    EXPECT_FALSE(s.name.empty()) << s.id;
    EXPECT_TRUE(s.hasElevation) << s.id;
    // Every site is in the northern hemisphere, south of Fairbanks (64.8 N), west of the Azores
    // (Lajes, 27.3 W) and east of Guam (144.8 E) going west.
    EXPECT_GT(s.latDeg, 13.0) << s.id;
    EXPECT_LT(s.latDeg, 66.0) << s.id;
    EXPECT_TRUE(s.lonDeg > 120.0 || s.lonDeg < -27.0) << s.id << " " << s.lonDeg;
  }
  const Station* ktlx = findStation(sites, "ktlx");
  ASSERT_NE(ktlx, nullptr);
  EXPECT_EQ(ktlx->name, "Oklahoma City, OK");
  EXPECT_NEAR(ktlx->latDeg, 35.333056, 1e-9);
  EXPECT_NEAR(ktlx->lonDeg, -97.277778, 1e-9);
  ASSERT_TRUE(ktlx->towerHeightMeters.has_value());
  EXPECT_EQ(*ktlx->towerHeightMeters, 15.0);
  const Station* guam = findStation(sites, "PGUA");
  ASSERT_NE(guam, nullptr);
  EXPECT_GT(guam->lonDeg, 144.0);
  EXPECT_EQ(findStation(sites, "KXYZ"), nullptr);
}

}  // namespace
}  // namespace atmoglobe::volume
