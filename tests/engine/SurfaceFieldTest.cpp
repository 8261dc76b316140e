// 2-D fields on the globe (SurfaceFieldGL, volume/SurfaceField.h): contour lines of an analytic
// field where they belong on the screen at three camera heights; the GPU fill against the CPU
// reference on a rectilinear and a curvilinear grid; isobaric surfaces; bad requests.
#include "GLTestUtil.h"
#include "SyntheticGridVolume.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/SurfaceFieldGL.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/SurfaceField.h>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>

namespace {
using namespace atmoglobe;

// One level at height 0 of value(lat, lon).
volume::GridVolume flatGrid(std::vector<double> lons, std::vector<double> lats,
                            const std::function<double(double, double)>& value) {
  volume::GridVolume g = testutil::rectilinearGrid(
      std::move(lons), std::move(lats), {0.0}, [](double, double) { return 0.0; },
      [&](double lat, double lon, double) { return value(lat, lon); });
  g.path = "test.nc";
  g.variable = "/f";
  g.units = "K";
  return g;
}

// Draws into a cleared frame as the scene renderer does (reverse-Z), returns the frame.
globe::ImageRGBA8 drawAlone(const engine::Camera& camera, engine::SurfaceFieldGL& s, bool fill, bool contours) {
  auto fb = engine::FramebufferGL::create(camera.widthPx(), camera.heightPx());
  EXPECT_TRUE(fb);
  (*fb)->bind();
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glClearDepth(0.0);
  glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (fill) s.drawFill(camera);
  if (contours) s.drawContours(camera);
  glFinish();
  return (*fb)->readColor();
}

// A field linear in latitude (value = latitude) has its 35.1 contour on the parallel at 35.1 N.
// Looking straight down on it from 5000, 500 and 50 km, in each pixel column of the middle half
// of the image the drawn line's centre (its coverage-weighted row) lies within 0.5 px of the
// parallel's projection there (the line is a screen-space quad 1.5 px wide, antialiased: its
// centroid is its centre line; the geodesics between its points leave the parallel by
// centimetres at this grid's 0.05-0.5 deg spacing).
TEST(SurfaceField, ContourLinesLieWithinHalfAPixelOfTheirTruePlaceAtThreeHeights) {
  testutil::glContext();
  for (const auto& [heightMeters, spacingDeg] : {std::pair{5e6, 0.5}, std::pair{5e5, 0.1}, std::pair{5e4, 0.05}}) {
    const double halfSpanDeg = std::max(3.0, heightMeters / 111e3 * 1.5);
    const int n = static_cast<int>(2.0 * halfSpanDeg / spacingDeg) + 1;
    auto field = volume::surfaceFieldOf(flatGrid(
        testutil::evenlySpaced(-97.0 - halfSpanDeg, spacingDeg, n),
        testutil::evenlySpaced(
            std::max(-89.0, 35.0 - halfSpanDeg), spacingDeg,
            static_cast<int>((std::min(89.0, 35.0 + halfSpanDeg) - std::max(-89.0, 35.0 - halfSpanDeg)) / spacingDeg) +
                1),
        [](double lat, double) { return lat; }));
    ASSERT_TRUE(field) << field.error();
    engine::SurfaceLayerDescription d;
    d.path = "test.nc";
    d.fill = false;
    d.contourValues = {35.1};
    d.contourColor = glm::vec3(1.0f);
    d.contourLabels = false;
    auto gl = engine::SurfaceFieldGL::create(engine::SurfaceData{std::move(*field), {}, {}, {}, {}}, d);
    ASSERT_TRUE(gl) << gl.error();
    ASSERT_EQ((*gl)->contours().size(), 1u);
    const engine::Camera camera(engine::CameraPose{35.1, -97.0, heightMeters, 0.0, -90.0, 0.0}, 45.0, 320, 180);
    const globe::ImageRGBA8 image = drawAlone(camera, **gl, false, true);
    // The parallel's row at each column centre, from its projection sampled finely.
    std::vector<glm::dvec2> track;
    for (double lon = -97.0 - halfSpanDeg; lon <= -97.0 + halfSpanDeg; lon += 1e-4 * halfSpanDeg)
      if (auto p = camera.projectToPixel(globe::geodeticToEcef({35.1, lon, 0.0}))) track.push_back(*p);
    double worst = 0.0, sum = 0.0;
    int columns = 0;
    for (int x = camera.widthPx() / 4; x < 3 * camera.widthPx() / 4; ++x) {
      const double cx = x + 0.5;
      double yTrue = std::nan("");
      for (std::size_t k = 0; k + 1 < track.size(); ++k)
        if ((track[k].x - cx) * (track[k + 1].x - cx) <= 0.0 && track[k].x != track[k + 1].x) {
          const double t = (cx - track[k].x) / (track[k + 1].x - track[k].x);
          yTrue = track[k].y + t * (track[k + 1].y - track[k].y);
          break;
        }
      ASSERT_TRUE(std::isfinite(yTrue));
      double weight = 0.0, moment = 0.0;
      for (int y = 0; y < camera.heightPx(); ++y) {
        const double w = image.at(x, y).a / 255.0;
        weight += w;
        moment += w * (y + 0.5);
      }
      ASSERT_GT(weight, 0.5) << "column " << x << " at " << heightMeters << " m: no line drawn";
      const double err = std::abs(moment / weight - yTrue);
      worst = std::max(worst, err);
      sum += err;
      ++columns;
    }
    std::cout << "contour at 35.1 N from " << heightMeters << " m: " << columns << " columns, mean error "
              << sum / columns << " px, worst " << worst << " px\n";
    EXPECT_LT(worst, 0.5) << heightMeters;
  }
}

// The fill: the GPU (a mesh of the grid points, values bilinear per fragment) against the CPU
// reference (each pixel's exact ellipsoid hit, the grid's horizontal interpolation, the colour
// table exactly) on a rectilinear grid seen obliquely and on a curvilinear one from above. What
// differs: the mesh's chords run below the ellipsoid (tens of metres in cells tens of kilometres
// wide), the table is tabulated at 1024 entries and interpolated, and float positions. Bound:
// mean below one 8-bit step and 35 dB, the volumes' GPU-vs-reference bounds.
TEST(SurfaceField, GpuFillMatchesTheCpuReference) {
  testutil::glContext();
  const auto smooth = [](double lat, double lon) {
    return 280.0 + 12.0 * std::sin(lat * 0.35) * std::cos(lon * 0.27) + 0.3 * (lat - 35.0);
  };
  // Rectilinear, 0.25 deg.
  volume::GridVolume rect =
      flatGrid(testutil::evenlySpaced(-110.0, 0.25, 121), testutil::evenlySpaced(25.0, 0.25, 81), smooth);
  // Curvilinear: a sheared, rotated grid (lat/lon of each point given).
  volume::GridVolume curv = rect;
  curv.curvilinear = true;
  curv.nx = 90;
  curv.ny = 70;
  curv.lonDeg.assign(curv.nx * curv.ny, 0.0);
  curv.latDeg.assign(curv.nx * curv.ny, 0.0);
  curv.values.assign(curv.nx * curv.ny, 0.0f);
  curv.heightAboveEllipsoidMeters.assign(curv.nx * curv.ny, 0.0f);
  for (std::size_t j = 0; j < curv.ny; ++j)
    for (std::size_t i = 0; i < curv.nx; ++i) {
      const double di = static_cast<double>(i), dj = static_cast<double>(j);
      const double lon = -108.0 + 0.2 * di + 0.06 * dj, lat = 27.0 + 0.18 * dj - 0.04 * di;
      curv.lonDeg[j * curv.nx + i] = lon;
      curv.latDeg[j * curv.nx + i] = lat;
      curv.values[j * curv.nx + i] = static_cast<float>(smooth(lat, lon));
    }
  // A missing point: the cells around it are not drawn by either.
  curv.values[30 * curv.nx + 40] = std::numeric_limits<float>::quiet_NaN();
  struct Case {
    const char* name;
    volume::GridVolume grid;
    engine::CameraPose pose;
  };
  for (Case& c : std::vector<Case>{{"rectilinear, oblique", rect, {28.0, -96.0, 6e5, -20.0, -35.0, 0.0}},
                                   {"curvilinear, from above", curv, {33.0, -99.0, 2.5e6, 0.0, -90.0, 0.0}}}) {
    auto field = volume::surfaceFieldOf(std::move(c.grid));
    ASSERT_TRUE(field) << field.error();
    engine::SurfaceLayerDescription d;
    d.path = "test.nc";
    d.opacity = 0.8;
    auto gl = engine::SurfaceFieldGL::create(engine::SurfaceData{std::move(*field), {}, {}, {}, {}}, d);
    ASSERT_TRUE(gl) << gl.error();
    const engine::Camera camera(c.pose, 45.0, 160, 90);
    const globe::ImageRGBA8 frame = drawAlone(camera, **gl, true, false);
    volume::VolumeImage gpu;
    gpu.widthPx = frame.width;
    gpu.heightPx = frame.height;
    int drawn = 0;
    for (int y = 0; y < frame.height; ++y)
      for (int x = 0; x < frame.width; ++x) {
        const glm::u8vec4 p = frame.at(x, y);
        gpu.rgbaPremultiplied.push_back(glm::dvec4(p.r, p.g, p.b, p.a) / 255.0);
        drawn += p.a > 0;
      }
    const volume::VolumeImage ref =
        volume::renderSurfaceReference((*gl)->sampler(), (*gl)->table(), d.opacity, engine::referenceCameraFor(camera));
    int refDrawn = 0;
    for (const glm::dvec4& p : ref.rgbaPremultiplied) refDrawn += p.a > 0.0;
    const volume::ImageError e = volume::compareImages(gpu, ref);
    std::cout << "surface fill, " << c.name << ": " << drawn << " pixels drawn (reference " << refDrawn << "), mean "
              << e.meanAbs << " max " << e.maxAbs << " PSNR " << e.psnrDb << " dB\n";
    EXPECT_GT(refDrawn, 2000) << c.name;
    EXPECT_LT(e.meanAbs, 1.0) << c.name;
    EXPECT_GT(e.psnrDb, 35.0) << c.name;
  }
}

TEST(SurfaceField, IsobaricSurfaceIsTheLevelsInterpolatedInLogPressure) {
  // Two pressure levels, 850 and 500 hPa, values 10 and 20: at 700 hPa
  // f = ln(850/700) / ln(850/500), the value 10 + 10 f.
  volume::GridVolume g = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 1.0, 3), testutil::evenlySpaced(0.0, 1.0, 3), {1500.0, 5500.0},
      [](double, double) { return 0.0; }, [](double, double, double h) { return h < 3000.0 ? 10.0 : 20.0; });
  g.path = "p.grib";
  g.variable = "t:isobaricInhPa";
  g.verticalKind = volume::VerticalKind::Pressure;
  g.levelValues = {850.0, 500.0};
  g.levelUnits = "hPa";
  auto s = volume::surfaceFieldOf(g, 70000.0);
  ASSERT_TRUE(s) << s.error();
  const double f = std::log(850.0 / 700.0) / std::log(850.0 / 500.0);
  EXPECT_NEAR(s->grid.values[4], 10.0 + 10.0 * f, 1e-5);
  EXPECT_EQ(s->name, "t at 700 hPa");
  const volume::SurfaceSampler sampler(*s);
  EXPECT_NEAR(sampler.valueAt(0.5, 0.5), 10.0 + 10.0 * f, 1e-5);
  EXPECT_TRUE(std::isnan(sampler.valueAt(10.0, 10.0)));  // outside the grid
  // A level's own pressure is that level.
  EXPECT_NEAR(volume::surfaceFieldOf(g, 50000.0)->grid.values[0], 20.0, 1e-6);
  // Errors: outside the levels, several levels and no pressure, not pressure levels.
  auto outside = volume::surfaceFieldOf(g, 30000.0);
  ASSERT_FALSE(outside);
  EXPECT_NE(outside.error().find("300 hPa is outside the levels of 't:isobaricInhPa', 850 to 500 hPa"),
            std::string::npos)
      << outside.error();
  auto noPressure = volume::surfaceFieldOf(g);
  ASSERT_FALSE(noPressure);
  EXPECT_NE(noPressure.error().find("has 2 levels: give a pressure level"), std::string::npos) << noPressure.error();
  // A level by its index, on any grid: the upper one, 20; beyond the levels, or with a pressure:
  // refused.
  auto upper = volume::surfaceFieldOf(g, std::nullopt, 1);
  ASSERT_TRUE(upper) << upper.error();
  EXPECT_EQ(upper->grid.values[4], 20.0f);
  EXPECT_EQ(upper->name, "t:isobaricInhPa at level 1");
  auto beyond = volume::surfaceFieldOf(g, std::nullopt, 2);
  ASSERT_FALSE(beyond);
  EXPECT_NE(beyond.error().find("level 2 asked, it has 2 (0 = the lowest)"), std::string::npos) << beyond.error();
  EXPECT_FALSE(volume::surfaceFieldOf(g, 70000.0, 0));
  g.verticalKind = volume::VerticalKind::HeightAboveSeaLevel;
  auto heights = volume::surfaceFieldOf(g, 70000.0);
  ASSERT_FALSE(heights);
  EXPECT_NE(heights.error().find("not pressure levels"), std::string::npos) << heights.error();
}

TEST(SurfaceField, IsobaricSurfaceOfTerrainFollowingLevelsTakesEachColumnsPressures) {
  // Three model levels whose pressures differ per column (a WRF, hybrid or sigma grid): column c
  // has p = (1000, 800, 600) hPa - 10 c hPa and values 10, 20, 30. The 700 hPa surface lies in
  // each column's own level pair, linear in ln(p); a column whose levels do not reach it has none.
  volume::GridVolume g = testutil::rectilinearGrid(
      testutil::evenlySpaced(0.0, 1.0, 3), testutil::evenlySpaced(0.0, 1.0, 3), {500.0, 2000.0, 4000.0},
      [](double, double) { return 0.0; },
      [](double, double, double h) { return h < 1000.0   ? 10.0
                                            : h < 3000.0 ? 20.0
                                                         : 30.0; });
  g.path = "wrf.nc";
  g.variable = "/tk";
  g.verticalKind = volume::VerticalKind::WrfEta;
  const std::size_t columns = g.nx * g.ny;
  g.pressurePa.resize(g.values.size());
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t c = 0; c < columns; ++c)
      g.pressurePa[k * columns + c] =
          static_cast<float>((100000.0 - 20000.0 * static_cast<double>(k)) - 1000.0 * static_cast<double>(c));
  // Column 8's top is at 520 hPa, column 7's at 530: the 525 hPa surface is in column 8 only.
  auto values = volume::isobaricColumnValues(g, 70000.0);
  ASSERT_TRUE(values) << values.error();
  for (std::size_t c = 0; c < columns; ++c) {
    const double pLow = 80000.0 - 1000.0 * static_cast<double>(c), pHigh = pLow - 20000.0;
    const double f = std::log(pLow / 70000.0) / std::log(pLow / pHigh);
    EXPECT_NEAR((*values)[c], 20.0 + 10.0 * f, 2e-5) << c;
  }
  auto top = volume::isobaricColumnValues(g, 52500.0);
  ASSERT_TRUE(top) << top.error();
  for (std::size_t c = 0; c < columns; ++c) EXPECT_EQ(std::isnan((*top)[c]), c < 8) << c;
  // Nearest level: the level nearer in ln(p).
  auto nearest = volume::isobaricColumnValues(g, 79000.0, true);
  ASSERT_TRUE(nearest);
  EXPECT_EQ((*nearest)[0], 20.0f);  // 800 hPa is nearer to 790 than 600
  EXPECT_EQ((*nearest)[8], 20.0f);  // its 720 hPa level
  // Above every column: an error that gives the pressures.
  auto above = volume::isobaricColumnValues(g, 40000.0);
  ASSERT_FALSE(above);
  EXPECT_NE(above.error().find("400 hPa is outside the levels of every column: their pressures run from 1000 hPa"),
            std::string::npos)
      << above.error();
  // The surface field takes the same values.
  auto s = volume::surfaceFieldOf(g, 70000.0);
  ASSERT_TRUE(s) << s.error();
  EXPECT_EQ(s->grid.values, *values);
  EXPECT_EQ(s->name, "tk at 700 hPa");
  // Pressures that do not match the values: an error, not a read past the end.
  g.pressurePa.pop_back();
  EXPECT_FALSE(volume::isobaricColumnValues(g, 70000.0));
}

TEST(SurfaceField, DescriptionsAreValidated) {
  engine::SurfaceLayerDescription d;
  d.path = "x.grib";
  EXPECT_TRUE(engine::validateSurfaceLayer(d, "s"));
  auto bad = [&](auto edit, const char* message) {
    engine::SurfaceLayerDescription e = d;
    edit(e);
    const Status st = engine::validateSurfaceLayer(e, "s");
    ASSERT_FALSE(st) << message;
    EXPECT_NE(st.error().find(message), std::string::npos) << st.error();
  };
  bad([](auto& e) { e.fill = false; }, "nothing to draw");
  bad([](auto& e) { e.wind = "u"; }, "expected auto or two variables U,V");
  bad([](auto& e) { e.opacity = 1.5; }, "opacity must be in 0..1");
  bad([](auto& e) { e.pressureHpa = -5.0; }, "pressure level must be in (0, 1100] hPa");
  bad([](auto& e) { e.contourInterval = 0.0; }, "contour interval must be a finite number > 0");
  bad([](auto& e) { e.valueRange = glm::dvec2(5.0, 1.0); }, "range must be two finite numbers");
  bad([](auto& e) { e.member = 2, e.ensemble = "mean"; }, "a member or an ensemble statistic, not both");
  bad([](auto& e) { e.ensemble = "median"; }, "median");
}

}  // namespace

// The viewer's map layers on the real ERA5 ensemble (10 members, z and t on 500 and 850 hPa):
// a statistic's layer keeps every member's field, whose values at a point are each member's map
// read alone, and whose mean is the statistic's value there; edits of the drawing keep the data,
// edits of the data read it again, a bad edit leaves the layer as it was; a map switched off is
// neither drawn nor read out.
TEST(SurfaceField, EnsembleMembersAndPanelEditsInTheScene) {
  const std::string era5 = atmoglobe_test::testDataPath("grids_grib/era5-levels-members.grib");
  SKIP_WITHOUT_TEST_DATA(era5);
  testutil::glContext();
  setenv("ATMOGLOBE_CACHE_DIR", atmoglobe_test::freshTestDir("surface_grib_cache").c_str(), 1);
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader) << loader.error();
  auto scene = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(scene) << scene.error();
  engine::SurfaceLayerDescription d;
  d.path = era5;
  d.variable = "t";
  d.pressureHpa = 500.0;
  d.ensemble = "mean";
  auto added = (*scene)->addSurface(d);
  ASSERT_TRUE(added) << added.error();
  const engine::SurfaceFieldGL& mean = *(*scene)->surfaces().at(0);
  const double lat = 51.3, lon = 2.7;  // between grid points
  const auto members = mean.memberValuesAt(lat, lon);
  ASSERT_EQ(members.size(), 10u);
  double sum = 0.0;
  for (std::size_t m = 0; m < members.size(); ++m) {
    EXPECT_EQ(members[m].first, static_cast<long>(m));  // GRIB numbers 0 .. 9
    engine::SurfaceLayerDescription one = d;
    one.ensemble.clear();
    one.member = static_cast<int>(m);
    auto alone = engine::readSurfaceData(one);
    ASSERT_TRUE(alone) << alone.error();
    const volume::SurfaceSampler sampler(alone->field);
    EXPECT_EQ(members[m].second, sampler.valueAt(lat, lon)) << m;
    sum += members[m].second;
  }
  // The mean of the members' maps is the map of the mean (the mean commutes with the linear
  // interpolations; float storage of ~250 K: 3e-5 K, summed over 10 members).
  EXPECT_NEAR(mean.sampler().valueAt(lat, lon), sum / 10.0, 2e-4);
  // The readout: the statistic's value, then each member's.
  const engine::Camera camera(engine::CameraPose{lat, lon, 2.0e6, 0.0, -90.0, 0.0}, 30.0, 64, 48);
  const engine::CursorReadout r = engine::readoutAt(**scene, camera, 32.0, 24.0);
  std::string all;
  for (const std::string& line : r.lines) all += line + "\n";
  EXPECT_NE(all.find("t at 500 hPa: "), std::string::npos) << all;
  EXPECT_NE(all.find(" K (mean)"), std::string::npos) << all;
  EXPECT_NE(all.find("  members (10): 0: "), std::string::npos) << all;

  // A drawing edit (opacity, contours) keeps the data: the same member values.
  engine::SurfaceLayerDescription drawn = d;
  drawn.opacity = 0.3;
  drawn.contourInterval = 2.0;
  ASSERT_TRUE((*scene)->setSurfaceDescription(0, drawn));
  EXPECT_EQ((*scene)->surfaces()[0]->memberValuesAt(lat, lon), members);
  EXPECT_FALSE((*scene)->surfaces()[0]->contours().empty());
  // A data edit reads again: 850 hPa, one member, no member fields.
  engine::SurfaceLayerDescription lower = drawn;
  lower.pressureHpa = 850.0;
  lower.ensemble.clear();
  lower.member = 3;
  ASSERT_TRUE((*scene)->setSurfaceDescription(0, lower));
  EXPECT_EQ((*scene)->surfaces()[0]->field().name, "t at 850 hPa");
  EXPECT_TRUE((*scene)->surfaces()[0]->memberValuesAt(lat, lon).empty());
  // A pressure outside the levels: an error, the layer unchanged.
  engine::SurfaceLayerDescription bad = lower;
  bad.pressureHpa = 1000.0;
  const Status st = (*scene)->setSurfaceDescription(0, bad);
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().find("1000 hPa is outside the levels"), std::string::npos) << st.error();
  EXPECT_EQ((*scene)->surfaces()[0]->field().name, "t at 850 hPa");
  // Switched off: no readout line, no legend entry.
  (*scene)->setSurfaceVisible(0, false);
  const engine::CursorReadout off = engine::readoutAt(**scene, camera, 32.0, 24.0);
  for (const std::string& line : off.lines) EXPECT_EQ(line.find("t at 850 hPa"), std::string::npos) << line;
  EXPECT_TRUE((*scene)->legendFor(camera).keys.empty());

  // A volume of the same statistic: its readout line gives each member's value at the first
  // value along the ray, and their mean is the statistic's value there (as printed: 4 digits).
  engine::VolumeLayerDescription grid;
  grid.kind = engine::VolumeKind::Grid;
  grid.path = era5;
  grid.field = "t";
  grid.ensemble = *volume::parseEnsembleStatistic("mean");
  auto layer = (*scene)->addVolume(grid);
  ASSERT_TRUE(layer) << layer.error();
  const engine::Camera oblique(engine::CameraPose{40.0, -20.0, 3.0e5, 0.0, -30.0, 0.0}, 30.0, 64, 48);
  const engine::CursorReadout v = engine::readoutAt(**scene, oblique, 32.0, 24.0);
  std::string text;
  for (const std::string& line : v.lines) text += line + "\n";
  const auto at = text.find("t:isobaricInhPa: ");
  ASSERT_NE(at, std::string::npos) << text;
  const double statistic = std::stod(text.substr(at + 17));
  const auto list = text.find("  members (10): ", at);
  ASSERT_NE(list, std::string::npos) << text;
  std::istringstream values(text.substr(list + 16, text.find('\n', list) - list - 16));
  double total = 0.0;
  int count = 0;
  for (std::string label; values >> label;) {
    double value = 0.0;
    values >> value;
    EXPECT_EQ(label, std::to_string(count) + ":");
    total += value;
    ++count;
  }
  ASSERT_EQ(count, 10) << text;
  // Both sides printed to 4 significant digits (0.05 K at 250 K): the mean of ten rounded values
  // and a rounded mean differ by at most 0.1 K.
  EXPECT_NEAR(total / count, statistic, 0.1) << text;
}
