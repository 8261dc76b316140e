// Slices on the globe (engine/SliceRendererGL.h, SliceLayer.h): the mesh lies where the slice's
// geometry says (float offsets from a double origin), the curtain bends at the path's points, the
// drawn patch shows the table's colour where its pixels are and nothing where they have no data,
// and scenes name slices with checked keys.
#include "GLTestUtil.h"
#include "SyntheticGridVolume.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/SliceRendererGL.h>
#include <atmoglobe/volume/GridSampler.h>

#include <gtest/gtest.h>

namespace {
using namespace atmoglobe;

// Worst distance (m) between the mesh's vertices and the geometry's positions of their (u, v).
double meshError(const engine::SliceMesh& m, const volume::SliceGeometry& g) {
  double worst = 0.0;
  for (std::size_t k = 0; k + 4 < m.vertices.size(); k += 5) {
    const glm::dvec3 p = m.originEcef + glm::dvec3(m.vertices[k], m.vertices[k + 1], m.vertices[k + 2]);
    const glm::dvec3 exact = g.ecefAt(double(m.vertices[k + 3]) * g.columns(), double(m.vertices[k + 4]) * g.rows());
    worst = std::max(worst, glm::length(p - exact));
  }
  return worst;
}
}  // namespace

TEST(SliceGlobe, MeshFollowsTheGeometryAndBendsAtThePathPoints) {
  volume::CrossSectionSpec spec;
  spec.points = {{34.7, -98.2}, {35.0, -97.8}, {35.4, -97.3}};
  spec.topMeters = 15000.0;
  spec.datum = volume::SliceHeightDatum::Ellipsoid;
  auto g = volume::SliceGeometry::crossSection(spec, nullptr);
  ASSERT_TRUE(g);
  const engine::SliceMesh m = engine::buildSliceMesh(*g);
  // Float offsets of at most ~60 km from the middle: 60 km x 6e-8 = 4 mm, plus the texture
  // coordinate's float rounding (6e-8 of 113 km = 7 mm along the path): under 2 cm.
  EXPECT_LT(meshError(m, *g), 0.02);
  // Every path point is a vertex of the curtain's top edge.
  for (const volume::LatLon& p : spec.points) {
    const glm::dvec3 top = globe::geodeticToEcef({p.latDeg, p.lonDeg, 15000.0});
    double nearest = 1e30;
    for (std::size_t k = 0; k + 4 < m.vertices.size(); k += 5) {
      nearest = std::min(
          nearest, glm::length(m.originEcef + glm::dvec3(m.vertices[k], m.vertices[k + 1], m.vertices[k + 2]) - top));
    }
    EXPECT_LT(nearest, 0.02);
  }
  volume::CappiSpec cappi;
  cappi.box = {33.0, 37.5, -100.0, -94.5};
  cappi.heightMeters = 3000.0;
  cappi.datum = volume::SliceHeightDatum::Ellipsoid;
  auto c = volume::SliceGeometry::cappi(cappi, nullptr);
  ASSERT_TRUE(c);
  const engine::SliceMesh cm = engine::buildSliceMesh(*c);
  EXPECT_LT(meshError(cm, *c), 0.05);  // 300 km offsets: 2 cm; texture coordinates: 3 cm
  // Cells of at most 5 km: the chord of a 5 km arc sags 5000^2 / (8 R) = 0.5 m below the surface.
  EXPECT_GE(cm.vertices.size() / 5, std::size_t(100 * 100));
}

// A CAPPI of a grid holding one value everywhere, seen from straight above: the pixels over the
// patch have the colour table's colour for that value, the pixels beyond the grid the globe's.
TEST(SliceGlobe, CappiPatchShowsTheTableColourWhereTheVolumeIs) {
  testutil::glContext();
  const volume::GridVolume grid = testutil::rectilinearGrid(
      testutil::evenlySpaced(-98.0, 0.5, 5), testutil::evenlySpaced(35.0, 0.5, 5), {0.0, 10000.0},
      [](double, double) { return 0.0; }, [](double, double, double) { return 42.0; });
  const volume::GridSampler sampler(grid);
  volume::CappiSpec spec;
  spec.box = {34.0, 38.0, -99.0, -95.0};  // larger than the grid (35..37, -98..-96)
  spec.heightMeters = 3000.0;
  spec.datum = volume::SliceHeightDatum::Ellipsoid;
  spec.columns = spec.rows = 64;
  auto g = volume::SliceGeometry::cappi(spec, nullptr);
  ASSERT_TRUE(g);
  const volume::SliceRaster raster = volume::sampleSlice({&sampler}, *g, volume::Interpolation::Linear);
  auto slices = engine::SliceRendererGL::create();
  ASSERT_TRUE(slices) << slices.error();
  const volume::ColorTable table = volume::nwsReflectivityTable();
  (*slices)->add(*g, raster, table, 1.0);
  const engine::Camera camera({36.0, -97.0, 6e5, 0.0, -90.0, 0.0}, 60.0, 200, 200);
  auto fb = engine::FramebufferGL::create(200, 200);
  ASSERT_TRUE(fb);
  testutil::beginReverseZ(**fb);
  (*slices)->draw(camera);
  glFinish();
  const globe::ImageRGBA8 img = (*fb)->readColor();
  const volume::Rgba8 c = table.map(42.0f);
  EXPECT_EQ(img.at(100, 100), glm::u8vec4(c.r, c.g, c.b, 255));  // over the grid's middle
  EXPECT_EQ(img.at(5, 100), glm::u8vec4(0, 0, 0, 255));          // beyond it: no data, nothing drawn
}

TEST(SliceGlobe, SceneSlicesAreParsedAndChecked) {
  auto scene = engine::parseSceneJson(
      R"({"slices": [{"radar": "@data/synthetic_ktlx.nc", "height_m": 3000, "box": [34, 36, -99, -96]},
                     {"grid": "g.nc", "variable": "dbz", "time": "2", "path": [[35, -98], [36, -97]],
                      "heights_m": [0, 12000], "datum": "ellipsoid", "opacity": 0.5}]})",
      "scene.json", "/base", "/data");
  ASSERT_TRUE(scene) << scene.error();
  ASSERT_EQ(scene->slices.size(), 2u);
  EXPECT_EQ(scene->slices[0].source.path, "/data/synthetic_ktlx.nc");
  EXPECT_TRUE(scene->slices[0].request.cappi);
  EXPECT_EQ(scene->slices[0].request.box->westDeg, -99.0);
  EXPECT_EQ(scene->slices[1].source.kind, volume::SliceSourceOptions::Kind::Grid);
  EXPECT_EQ(scene->slices[1].source.path, "/base/g.nc");
  EXPECT_EQ(scene->slices[1].request.path.size(), 2u);
  EXPECT_EQ(scene->slices[1].request.datum, volume::SliceHeightDatum::Ellipsoid);
  EXPECT_EQ(scene->slices[1].opacity, 0.5);
  for (auto [text, message] :
       {std::pair{R"({"slices": [{"radar": "a.nc", "height_m": 1, "hieght": 2}]})",
                  "scene.json: /slices/0/hieght: unknown key \"hieght\""},
        std::pair{R"({"slices": [{"radar": "a.nc"}]})", "\"height_m\" (a CAPPI) or \"path\""},
        std::pair{R"({"slices": [{"radar": "a.nc", "path": [[35, -98]]}]})", "at least two points"},
        std::pair{R"({"slices": [{"height_m": 1000}]})", "needs a \"radar\" or a \"grid\""},
        std::pair{R"({"slices": [{"radar": "a.nc", "grid": "b.nc", "height_m": 1}]})", "not both"},
        std::pair{R"({"slices": [{"radar": "a.nc", "height_m": 1, "opacity": 2}]})", "opacity"}}) {
    auto bad = engine::parseSceneJson(text, "scene.json", "", "");
    ASSERT_FALSE(bad) << text;
    EXPECT_NE(bad.error().find(message), std::string::npos) << bad.error();
  }
}
