// The bad-input suite of vector overlays (map/VectorFile.h readVectorFile through GDAL/OGR;
// docs/robustness.md "Bad-input suite"): GeoJSON, KML and a shapefile written here,
// truncated at 32 offsets and bit-flipped, plus NaN, infinite and beyond-90 coordinates, wrong
// types, deep nesting, empty layers and a shapefile whose headers claim 2^31 records. Each case
// runs in a child with a time limit and a memory cap (tests/BoundedRun.h): it reads, or fails with
// an error naming the file; never a crash, a hang or an allocation the file cannot back.
#include <atmoglobe/map/VectorFile.h>

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "BoundedRun.h"

using namespace atmoglobe;
using atmoglobe_test::BoundedOutcome;

namespace {

using Bytes = std::vector<unsigned char>;

// Time: the slowest case takes ~0.1 s (GDAL's driver registration is done before the cases);
// 10 s leaves room for sanitizers on a loaded machine. Memory: GDAL's own state (driver
// metadata, a few MB) plus 1100 x the input (zlib's largest expansion, for KMZ/compressed
// inputs); 64 MiB is ~10x the largest growth measured for an intact input.
constexpr unsigned kCaseSeconds = 10;
std::size_t memoryCapBytes(std::size_t inputBytes) { return (std::size_t{64} << 20) + 1100 * inputBytes; }

Bytes readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void writeAll(const std::string& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}
Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

struct Tally {
  std::string format;
  int cases = 0, errors = 0, reads = 0;
  long maxGrowthKb = 0;
  double maxSeconds = 0.0;
  ~Tally() {
    std::printf("[ tally    ] %s: %d cases, %d errors, %d read; max peak-RSS growth %ld kB, max %.2f s\n",
                format.c_str(), cases, errors, reads, maxGrowthKb, maxSeconds);
  }
};

/// Reads `path`: the error, or nullopt when it read (with at least one line, finite lon/lat).
std::optional<std::string> readOverlay(const std::string& path) {
  auto c = map::readVectorFile(path);
  if (!c) return c.error();
  for (const auto& line : c->lines)
    for (const auto& p : line.lonLatDeg)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || std::abs(p.y) > 90.0)
        return std::optional<std::string>("read a point off the Earth");  // does not name the file: fails
  return std::nullopt;
}

BoundedOutcome runCase(Tally& t, const std::string& what, const std::string& path, std::size_t inputBytes) {
  const std::size_t cap = memoryCapBytes(inputBytes);
  BoundedOutcome o = atmoglobe_test::runBounded([&] { return readOverlay(path); }, kCaseSeconds, cap);
  ++t.cases;
  t.maxGrowthKb = std::max(t.maxGrowthKb, o.rssGrowthKb);
  t.maxSeconds = std::max(t.maxSeconds, o.seconds);
  EXPECT_TRUE(o.kind == BoundedOutcome::Kind::Read || o.kind == BoundedOutcome::Kind::Error)
      << t.format << " " << what << ": " << atmoglobe_test::toString(o.kind) << " (" << o.message << ")\n"
      << o.backtrace;
  EXPECT_LE(static_cast<std::size_t>(std::max(0L, o.rssGrowthKb)) * 1024, cap)
      << t.format << " " << what << ": peak resident set grew by " << o.rssGrowthKb << " kB";
  if (o.kind == BoundedOutcome::Kind::Error) {
    ++t.errors;
    EXPECT_EQ(o.message.rfind(path, 0), 0u)
        << t.format << " " << what << ": the error does not name the file: " << o.message;
  }
  if (o.kind == BoundedOutcome::Kind::Read) ++t.reads;
  return o;
}

void expectRefused(Tally& t, const std::string& what, const std::string& path, const Bytes& bytes,
                   std::initializer_list<const char*> fragments) {
  writeAll(path, bytes);
  const BoundedOutcome o = runCase(t, what, path, bytes.size());
  ASSERT_EQ(o.kind, BoundedOutcome::Kind::Error)
      << t.format << " " << what << " was " << atmoglobe_test::toString(o.kind) << ": " << o.message;
  std::printf("[ refused  ] %s, %s: %s\n", t.format.c_str(), what.c_str(), o.message.c_str());
  for (const char* f : fragments)
    EXPECT_NE(o.message.find(f), std::string::npos)
        << t.format << " " << what << ": no '" << f << "' in: " << o.message;
}

/// Truncated at 32 offsets (0 included) and 24 variants with 1 to 4 flipped bits.
void mutations(Tally& t, const std::string& dir, const std::string& stem, const std::string& ext, const Bytes& whole,
               std::uint32_t seed) {
  for (std::size_t k = 0; k < 32; ++k) {
    const std::size_t cut = whole.size() * k / 32;
    const std::string path = dir + "/" + stem + "-cut" + std::to_string(cut) + ext;
    writeAll(path, Bytes(whole.begin(), whole.begin() + static_cast<long>(cut)));
    runCase(t, std::string("truncated at ").append(std::to_string(cut)), path, cut + 1);
  }
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> at(0, whole.size() - 1);
  std::uniform_int_distribution<int> bit(0, 7), count(1, 4);
  for (int i = 0; i < 24; ++i) {
    Bytes b = whole;
    for (int n = count(rng); n > 0; --n) b[at(rng)] ^= static_cast<unsigned char>(1u << bit(rng));
    const std::string path = dir + "/" + stem + "-flip" + std::to_string(i) + ext;
    writeAll(path, b);
    runCase(t, "bits flipped", path, b.size());
  }
}

const char* kGeoJson = R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {"name": "track"}, "geometry": {"type": "LineString", "coordinates": [[-97.5, 35.2], [-97.4, 35.3], [-97.3, 35.25]]}},
 {"type": "Feature", "properties": {"name": "box"}, "geometry": {"type": "Polygon", "coordinates": [[[-98, 35], [-97, 35], [-97, 36], [-98, 35]]]}},
 {"type": "Feature", "properties": {}, "geometry": {"type": "MultiLineString", "coordinates": [[[5, 5], [6, 6]], [[7, 7], [8, 8]]]}}]})";

std::string geoJsonLine(const std::string& coordinates) {
  return R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": )" +
         coordinates + "}}]}";
}

const char* kKml = R"(<?xml version="1.0" encoding="UTF-8"?>
<kml xmlns="http://www.opengis.net/kml/2.2"><Document><name>overlay</name>
<Placemark><name>track</name><LineString><coordinates>-97.5,35.2,0 -97.4,35.3,0 -97.3,35.25,0</coordinates></LineString></Placemark>
<Placemark><name>area</name><Polygon><outerBoundaryIs><LinearRing><coordinates>-98,35 -97,35 -97,36 -98,35</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>
</Document></kml>
)";

std::string kmlLine(const std::string& coordinates) {
  return std::string(R"(<?xml version="1.0" encoding="UTF-8"?>
<kml xmlns="http://www.opengis.net/kml/2.2"><Document><Placemark><LineString><coordinates>)") +
         coordinates + "</coordinates></LineString></Placemark></Document></kml>\n";
}

/// Two line strings written through OGR's `driver` (a shapefile: 3 files).
void writeOgr(const std::string& shp, const char* driver = "ESRI Shapefile") {
  GDALAllRegister();
  GDALDriverH drv = GDALGetDriverByName(driver);
  ASSERT_NE(drv, nullptr);
  GDALDatasetH ds = GDALCreate(drv, shp.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  ASSERT_NE(ds, nullptr);
  OGRLayerH layer = GDALDatasetCreateLayer(ds, "lines", nullptr, wkbLineString, nullptr);
  ASSERT_NE(layer, nullptr);
  for (int f = 0; f < 2; ++f) {
    OGRFeatureH feat = OGR_F_Create(OGR_L_GetLayerDefn(layer));
    OGRGeometryH g = OGR_G_CreateGeometry(wkbLineString);
    for (int i = 0; i < 4; ++i) OGR_G_AddPoint_2D(g, -97.0 + f + 0.1 * i, 35.0 + 0.1 * i);
    OGR_F_SetGeometryDirectly(feat, g);
    ASSERT_EQ(OGR_L_CreateFeature(layer, feat), OGRERR_NONE);
    OGR_F_Destroy(feat);
  }
  GDALClose(ds);
}

void put32be(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<unsigned char>(v >> (24 - 8 * i));
}
void put32le(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<unsigned char>(v >> (8 * i));
}

}  // namespace

TEST(CorruptInput, OverlayGeoJsonEveryCase) {
  Tally t{"overlay GeoJSON"};
  const std::string dir = atmoglobe_test::freshTestDir("corrupt_overlay_geojson");
  const std::string good = dir + "/good.geojson";
  writeAll(good, text(kGeoJson));
  ASSERT_FALSE(readOverlay(good)) << *readOverlay(good);  // also registers GDAL's drivers before the cases
  mutations(t, dir, "gj", ".geojson", text(kGeoJson), 21u);
  expectRefused(t, "NaN coordinate", dir + "/nan.geojson", text(geoJsonLine("[[NaN, 35], [-97, 36]]")), {});
  expectRefused(t, "infinite coordinate (1e999)", dir + "/inf.geojson", text(geoJsonLine("[[1e999, 35], [-97, 36]]")),
                {});
  expectRefused(t, "latitude 91", dir + "/lat91.geojson", text(geoJsonLine("[[-97, 91], [-97, 36]]")),
                {"not a longitude/latitude"});
  expectRefused(t, "coordinates of type string", dir + "/strings.geojson",
                text(geoJsonLine(R"([["-97", "35"], ["-97", "36"]])")), {});
  expectRefused(t, "no features (an empty layer)", dir + "/empty.geojson",
                text(R"({"type": "FeatureCollection", "features": []})"), {"no line or polygon"});
  expectRefused(t, "only points", dir + "/points.geojson", text(R"({"type": "Point", "coordinates": [1, 2]})"),
                {"no line or polygon"});
  {  // 20000 nested geometry collections around one line: GDAL refuses deep nesting or we recurse.
    std::string nested = R"({"type": "LineString", "coordinates": [[0, 0], [1, 1]]})";
    for (int i = 0; i < 20000; ++i) nested = R"({"type": "GeometryCollection", "geometries": [)" + nested + "]}";
    const std::string path = dir + "/nested.geojson";
    writeAll(path, text(nested));
    const auto o = runCase(t, "20000 nested collections", path, nested.size());
    std::printf("[ outcome  ] %s, %s: %s %s\n", t.format.c_str(), "20000 nested collections",
                atmoglobe_test::toString(o.kind), o.message.c_str());
  }
  {  // A CRS PROJ does not know (EPSG:999999): GDAL's GeoJSON driver falls back to WGS 84; the
     // reader must say so instead of taking the coordinates as longitude/latitude.
    const std::string crs =
        R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::999999"}},
      "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[0, 0], [1, 1]]}}]})";
    expectRefused(t, "unknown CRS (EPSG:999999)", dir + "/badcrs.geojson", text(crs), {"CRS"});
  }
}

TEST(CorruptInput, OverlayKmlEveryCase) {
  Tally t{"overlay KML"};
  const std::string dir = atmoglobe_test::freshTestDir("corrupt_overlay_kml");
  const std::string good = dir + "/good.kml";
  writeAll(good, text(kKml));
  ASSERT_FALSE(readOverlay(good)) << *readOverlay(good);
  mutations(t, dir, "kml", ".kml", text(kKml), 22u);
  expectRefused(t, "NaN coordinate", dir + "/nan.kml", text(kmlLine("nan,35 -97,36")), {});
  expectRefused(t, "infinite coordinate", dir + "/inf.kml", text(kmlLine("-97,inf -97,36")), {});
  expectRefused(t, "latitude 95", dir + "/lat95.kml", text(kmlLine("-97,95 -97,36")), {});
  expectRefused(t, "words for coordinates", dir + "/words.kml", text(kmlLine("west,north east,south")), {});
  expectRefused(t, "no placemark", dir + "/empty.kml",
                text(R"(<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document/></kml>)"), {});
  {  // A NetworkLink to an address that cannot be reached: no fetch may hang the read.
    const std::string link = std::string(R"(<?xml version="1.0"?><kml xmlns="http://www.opengis.net/kml/2.2"><Document>
<NetworkLink><Link><href>http://192.0.2.1/overlay.kml</href></Link></NetworkLink>
<Placemark><LineString><coordinates>0,0 1,1</coordinates></LineString></Placemark></Document></kml>)");
    const std::string path = dir + "/networklink.kml";
    writeAll(path, text(link));
    const auto o = runCase(t, "network link to an unreachable host", path, link.size());
    std::printf("[ outcome  ] %s, %s: %s %s\n", t.format.c_str(), "network link to an unreachable host",
                atmoglobe_test::toString(o.kind), o.message.c_str());
  }
}

TEST(CorruptInput, OverlayShapefileEveryCase) {
  Tally t{"overlay shapefile"};
  const std::string dir = atmoglobe_test::freshTestDir("corrupt_overlay_shp");
  const std::string good = dir + "/good.shp";
  writeOgr(good);
  ASSERT_FALSE(readOverlay(good)) << *readOverlay(good);
  const Bytes shp = readAll(good), shx = readAll(dir + "/good.shx"), dbf = readAll(dir + "/good.dbf");
  ASSERT_GT(shp.size(), 100u);
  // Truncations and flips of the .shp (its .shx and .dbf copied beside each variant).
  auto variant = [&](const std::string& stem, const Bytes& s, const Bytes& x, const Bytes& d) {
    writeAll(dir + "/" + stem + ".shx", x);
    writeAll(dir + "/" + stem + ".dbf", d);
    const std::string path = dir + "/" + stem + ".shp";
    writeAll(path, s);
    return path;
  };
  for (std::size_t k = 0; k < 32; ++k) {
    const std::size_t cut = shp.size() * k / 32;
    const std::string path =
        variant("cut" + std::to_string(cut), Bytes(shp.begin(), shp.begin() + static_cast<long>(cut)), shx, dbf);
    runCase(t, std::string(".shp truncated at ").append(std::to_string(cut)), path, cut + 1);
  }
  std::mt19937 rng(23);
  std::uniform_int_distribution<std::size_t> at(0, shp.size() - 1);
  std::uniform_int_distribution<int> bit(0, 7);
  for (int i = 0; i < 24; ++i) {
    Bytes b = shp;
    for (int n = 0; n < 1 + i % 4; ++n) b[at(rng)] ^= static_cast<unsigned char>(1u << bit(rng));
    runCase(t, ".shp bits flipped", variant("flip" + std::to_string(i), b, shx, dbf), b.size());
  }
  {  // Headers claiming terabytes: .shp file length (big-endian 16-bit words, byte 24) 2^31 - 1
     // words (4 GB), the first record's content length 2^31 - 1 words, the .dbf record count
     // (little-endian, byte 4) 2^31 - 1, the .shx length too.
    Bytes s = shp, x = shx, d = dbf;
    put32be(s, 24, 0x7fffffffu);
    put32be(s, 104, 0x7fffffffu);
    put32be(x, 24, 0x7fffffffu);
    put32le(d, 4, 0x7fffffffu);
    const std::string path = variant("huge", s, x, d);
    const auto o = runCase(t, "headers claiming 2^31 records and 4 GB", path, s.size() + x.size() + d.size());
    std::printf("[ outcome  ] %s, huge headers: %s %s\n", t.format.c_str(), atmoglobe_test::toString(o.kind),
                o.message.c_str());
  }
  {  // NaN and beyond-90 coordinates (the first point of the first record: after the file header
     // (100), the record header (8), type, bounding box, part and point counts (44) and the one
     // part index (4); x then y, little-endian doubles) must not read as points on the Earth.
    for (const double bad : {std::numeric_limits<double>::quiet_NaN(), 95.0}) {
      Bytes s = shp;
      std::memcpy(&s[100 + 8 + 44 + 4 + 8], &bad, 8);
      const std::string stem = std::isnan(bad) ? "nanlat" : "lat95";
      const std::string path = variant(stem, s, shx, dbf);
      const auto o = runCase(t, stem, path, s.size());
      EXPECT_EQ(o.kind, BoundedOutcome::Kind::Error) << stem << ": " << o.message;
      std::printf("[ refused  ] %s, %s: %s\n", t.format.c_str(), stem.c_str(), o.message.c_str());
    }
  }
  {  // A .shp without its .shx and .dbf.
    const std::string path = dir + "/alone.shp";
    writeAll(path, shp);
    const auto o = runCase(t, ".shp without .shx and .dbf", path, shp.size());
    std::printf("[ outcome  ] %s, %s: %s %s\n", t.format.c_str(), ".shp without .shx and .dbf",
                atmoglobe_test::toString(o.kind), o.message.c_str());
  }
}

TEST(CorruptInput, OverlayGeoPackageEveryCase) {
  Tally t{"overlay GeoPackage"};
  const std::string dir = atmoglobe_test::freshTestDir("corrupt_overlay_gpkg");
  const std::string good = dir + "/good.gpkg";
  writeOgr(good, "GPKG");
  ASSERT_FALSE(readOverlay(good)) << *readOverlay(good);
  const Bytes whole = readAll(good);
  ASSERT_GT(whole.size(), 1000u);
  mutations(t, dir, "gpkg", ".gpkg", whole, 24u);
  {  // The SQLite header's page count (big-endian, byte 28) claiming 2^31 - 1 pages (8 TB at 4 kB).
    Bytes b = whole;
    put32be(b, 28, 0x7fffffffu);
    const std::string path = dir + "/huge.gpkg";
    writeAll(path, b);
    const auto o = runCase(t, "page count claiming 8 TB", path, b.size());
    std::printf("[ outcome  ] %s, huge page count: %s %s\n", t.format.c_str(), atmoglobe_test::toString(o.kind),
                o.message.c_str());
  }
}
