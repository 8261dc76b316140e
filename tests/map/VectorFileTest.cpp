// User vector files through GDAL/OGR: the shared Natural Earth shapefile, GeoJSON written here
// (a line across the antimeridian, a polygon, a projected CRS), and bad input.
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/map/VectorFile.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace atmoglobe;

namespace {
std::string writeFile(const std::string& name, const std::string& text) {
  const std::string dir = ATMOGLOBE_TEST_OUTPUT_DIR;
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}
}  // namespace

TEST(VectorFile, NaturalEarthBoundaryLinesShapefile) {
  const std::string shp = atmoglobe_test::testDataPath("overlays/ne_10m_admin_0_boundary_lines_land.shp");
  SKIP_WITHOUT_TEST_DATA(shp);
  auto c = map::readVectorFile(shp);
  ASSERT_TRUE(c) << c.error();
  // Natural Earth 10m land boundaries: several hundred polyline features (ogrinfo: 462 in v4.1;
  // any release has hundreds), no polygons, WGS 84.
  EXPECT_GT(c->features, 200u);
  EXPECT_EQ(c->rings, 0u);
  EXPECT_GE(c->lineStrings, c->features);
  ASSERT_EQ(c->layerCrs.size(), 1u);
  EXPECT_NE(c->layerCrs[0].find("WGS"), std::string::npos) << c->layerCrs[0];
  // The France-Germany-Switzerland tripoint (47.5899 N, 7.5886 E) is on a line: within 1 km
  // (1:10m data is ~ 1 km at worst); Paris is not within 100 km of any.
  auto nearest = [&](double lon, double lat) {
    double best = 1e300;
    for (const auto& l : c->lines)
      for (const glm::dvec2& p : l.lonLatDeg)
        if (std::abs(p.y - lat) < 2.0 && std::abs(p.x - lon) < 3.0)
          best = std::min(best, globe::geodesicInverse(lat, lon, p.y, p.x).distanceMeters);
    return best;
  };
  EXPECT_LT(nearest(7.5886, 47.5899), 1000.0);
  EXPECT_GT(nearest(2.3522, 48.8566), 100000.0);
}

TEST(VectorFile, GeoJsonLinesPolygonsAndTheAntimeridian) {
  const std::string path = writeFile("overlay.geojson", R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "properties": {"name": "dateline"},
     "geometry": {"type": "LineString", "coordinates": [[170, 10], [-170, 20]]}},
    {"type": "Feature", "properties": {"name": "box"},
     "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]],
                                                      [[0.2, 0.2], [0.4, 0.2], [0.4, 0.4], [0.2, 0.2]]]}},
    {"type": "Feature", "properties": {},
     "geometry": {"type": "MultiLineString", "coordinates": [[[5, 5], [6, 6]], [[7, 7], [8, 8], [9, 7]]]}},
    {"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [3, 3]}}]})");
  auto c = map::readVectorFile(path);
  ASSERT_TRUE(c) << c.error();
  EXPECT_EQ(c->features, 4u);
  EXPECT_EQ(c->lineStrings, 3u);
  EXPECT_EQ(c->rings, 2u);
  EXPECT_EQ(c->points, 1u);
  ASSERT_EQ(c->lines.size(), 5u);
  EXPECT_EQ(c->lines[0].lonLatDeg[1], glm::dvec2(-170.0, 20.0));  // kept as given: split when drawn
  EXPECT_EQ(c->lines[1].lonLatDeg.size(), 5u);                    // closed ring
  EXPECT_EQ(c->lines[1].lonLatDeg.front(), c->lines[1].lonLatDeg.back());
  EXPECT_EQ(c->lines[4].lonLatDeg.size(), 3u);
  const auto pieces = map::splitAtAntimeridian(c->lines[0]);
  EXPECT_EQ(pieces.size(), 2u);
}

TEST(VectorFile, ProjectedCrsIsTransformedToLonLat) {
  // Web mercator (EPSG:3857) coordinates of (10 E, 50 N) and (12 E, 52 N) from the spherical
  // formulas (x = R lon, y = R ln tan(pi/4 + lat/2), R = 6378137 m), independent of GDAL/PROJ.
  const double R = 6378137.0, d = M_PI / 180.0;
  auto x = [&](double lon) { return R * lon * d; };
  auto y = [&](double lat) { return R * std::log(std::tan(M_PI / 4.0 + lat * d / 2.0)); };
  char text[1024];
  std::snprintf(text, sizeof text, R"({"type": "FeatureCollection",
    "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::3857"}},
    "features": [{"type": "Feature", "properties": {},
      "geometry": {"type": "LineString", "coordinates": [[%.6f, %.6f], [%.6f, %.6f]]}}]})",
                x(10.0), y(50.0), x(12.0), y(52.0));
  auto c = map::readVectorFile(writeFile("mercator.geojson", text));
  ASSERT_TRUE(c) << c.error();
  ASSERT_EQ(c->lines.size(), 1u);
  EXPECT_NE(c->layerCrs[0].find("Pseudo-Mercator"), std::string::npos) << c->layerCrs[0];
  // 1e-6 m of easting/northing written (%.6f) is ~1e-11 deg: 1e-8 deg is rounding headroom.
  EXPECT_NEAR(c->lines[0].lonLatDeg[0].x, 10.0, 1e-8);
  EXPECT_NEAR(c->lines[0].lonLatDeg[0].y, 50.0, 1e-8);
  EXPECT_NEAR(c->lines[0].lonLatDeg[1].x, 12.0, 1e-8);
  EXPECT_NEAR(c->lines[0].lonLatDeg[1].y, 52.0, 1e-8);
}

TEST(VectorFile, BadInputNamesTheFileAndTheProblem) {
  auto missing = map::readVectorFile("/nonexistent/counties.shp");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("/nonexistent/counties.shp: no such file"), std::string::npos) << missing.error();
  const std::string garbage = writeFile("garbage.geojson", "{ this is not json");
  auto bad = map::readVectorFile(garbage);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find(garbage), std::string::npos) << bad.error();
  const std::string pointsOnly = writeFile("points.geojson", R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [3, 3]}}]})");
  auto points = map::readVectorFile(pointsOnly);
  ASSERT_FALSE(points);
  EXPECT_NE(points.error().find("no line or polygon"), std::string::npos) << points.error();
  // Lon/lat data mislabelled: degrees outside the Earth.
  const std::string offEarth = writeFile("off_earth.geojson", R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[500000, 5000000], [1, 1]]}}]})");
  auto off = map::readVectorFile(offEarth);
  ASSERT_FALSE(off);
  EXPECT_NE(off.error().find("not a longitude/latitude"), std::string::npos) << off.error();
}

// Overlays are read with a fixed list of GDAL drivers: a file another driver would open (here a
// minimal DXF drawing and an OpenStreetMap XML file, both holding a line) is refused with its
// format named, never parsed.
TEST(VectorFile, OtherGdalFormatsAreRefusedWithTheirFormatNamed) {
  const std::string dxf = writeFile("drawing.dxf",
                                    "0\nSECTION\n2\nENTITIES\n0\nLINE\n8\n0\n10\n1.0\n20\n1.0\n11\n2.0\n21\n2.0\n0\n"
                                    "ENDSEC\n0\nEOF\n");
  auto d = map::readVectorFile(dxf);
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().find(dxf + ": format AutoCAD DXF (GDAL driver DXF), which overlays do not read"),
            std::string::npos)
      << d.error();
  EXPECT_NE(d.error().find("GeoJSON"), std::string::npos) << d.error();
  const std::string osm = writeFile("streets.osm", R"(<?xml version="1.0"?>
<osm version="0.6"><node id="1" lat="1" lon="1"/><node id="2" lat="2" lon="2"/>
<way id="3"><nd ref="1"/><nd ref="2"/><tag k="highway" v="primary"/></way></osm>)");
  auto o = map::readVectorFile(osm);
  ASSERT_FALSE(o);
  EXPECT_NE(o.error().find(osm + ": format OpenStreetMap XML and PBF (GDAL driver OSM)"), std::string::npos)
      << o.error();
  // Not a format GDAL knows at all: the list of what is read.
  const std::string text = writeFile("notes.geojson", "rain at noon\n");
  auto t = map::readVectorFile(text);
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().find(text + ": not a vector file of a format overlays read (GeoJSON, GeoJSONSeq"),
            std::string::npos)
      << t.error();
}
