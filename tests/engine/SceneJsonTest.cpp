// Scene JSON (engine/Scene.h): errors name the JSON pointer and the problem; every example in
// assets/scenes/ parses. GL-free.
#include <atmoglobe/engine/Scene.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

using namespace atmoglobe;

namespace {
// The error of a scene that must not parse.
std::string errorOf(const std::string& text) {
  auto scene = engine::parseSceneJson(text, "scene.json", "/base", "/data");
  EXPECT_FALSE(scene) << text;
  return scene ? std::string() : scene.error();
}
}  // namespace

TEST(SceneJson, UnknownKeysNameTheirPointerAndTheClosestKey) {
  EXPECT_EQ(errorOf(R"({"camera": {"lat_deg": 1, "hieght_m": 1000}})"),
            "scene.json: /camera/hieght_m: unknown key \"hieght_m\" (did you mean \"height_m\"?)");
  EXPECT_EQ(errorOf(R"({"radar": []})"), "scene.json: /radar: unknown key \"radar\" (did you mean \"radars\"?)");
  EXPECT_EQ(errorOf(R"({"radars": [{"path": "a.nc"}, {"path": "b.nc", "feild": "VEL"}]})"),
            "scene.json: /radars/1/feild: unknown key \"feild\" (did you mean \"field\"?)");
  // Nothing close: the keys allowed there are listed.
  const std::string far = errorOf(R"({"overlays": [{"path": "x.geojson", "zzzzzz": 1}]})");
  EXPECT_EQ(far, "scene.json: /overlays/0/zzzzzz: unknown key \"zzzzzz\" (keys here: path color width_px)");
  // Pointer tokens are escaped (RFC 6901).
  EXPECT_EQ(errorOf(R"({"a/b~c": 1})").rfind("scene.json: /a~1b~0c: unknown key", 0), 0u);
}

TEST(SceneJson, WrongTypesSayWhatWasExpectedAndWhatCame) {
  EXPECT_EQ(errorOf(R"({"camera": {"height_m": "high"}})"),
            "scene.json: /camera/height_m: expected a number, got string");
  EXPECT_EQ(errorOf(R"({"grids": [{"path": "g.nc", "time": 3}]})"),
            "scene.json: /grids/0/time: expected a string, got integer");
  EXPECT_EQ(errorOf(R"({"map_context": "yes"})"), "scene.json: /map_context: expected true or false, got string");
  EXPECT_EQ(errorOf(R"({"radars": {"path": "a.nc"}})"), "scene.json: /radars: expected an array, got object");
  EXPECT_EQ(errorOf(R"({"radars": [{"path": "a.nc", "range": [0, "70"]}]})"),
            "scene.json: /radars/0/range/1: expected a number, got string");
  EXPECT_EQ(errorOf(R"({"size": [640.5, 480]})"), "scene.json: /size/0: expected an integer, got number");
  EXPECT_EQ(errorOf(R"({"markers": [[1, 2]]})"), "scene.json: /markers/0: expected an object, got array");
  EXPECT_EQ(errorOf(R"([1, 2])"), "scene.json: /: expected an object, got array");
  EXPECT_EQ(errorOf(R"({"slices": [{"radar": 5, "height_m": 1000}]})"),
            "scene.json: /slices/0/radar: expected a string, got integer");
}

TEST(SceneJson, OutOfRangeValuesNameTheRange) {
  EXPECT_EQ(errorOf(R"({"radars": [{"path": "a.nc"}, {"path": "b.nc"}, {"path": "c.nc", "step_m": 0}]})"),
            "scene.json: /radars/2/step_m: 0 is out of range 1..1e+06 m");
  EXPECT_EQ(errorOf(R"({"camera": {"lat_deg": 95}})"), "scene.json: /camera/lat_deg: 95 is out of range -90..90 deg");
  EXPECT_EQ(errorOf(R"({"size": [0, 480]})"), "scene.json: /size/0: 0 is out of range 1..16384");
  EXPECT_EQ(errorOf(R"({"markers": [{"lat_deg": 1, "lon_deg": 2, "color": [1, 2, 0]}]})"),
            "scene.json: /markers/0/color/1: 2 is out of range 0..1");
  EXPECT_EQ(errorOf(R"({"slices": [{"radar": "a.nc", "height_m": 1000, "opacity": 2}]})"),
            "scene.json: /slices/0/opacity: 2 is out of range 0..1");
  EXPECT_EQ(errorOf(R"({"slices": [{"radar": "a.nc", "height_m": 1000, "resolution_px": 10}]})"),
            "scene.json: /slices/0/resolution_px: 10 is out of range 64..4096 px");
  EXPECT_EQ(errorOf(R"({"fov_deg": 0})"), "scene.json: /fov_deg: must be above 0 and below 180 deg");
  EXPECT_EQ(errorOf(R"({"overlays": [{"path": "x.geojson", "width_px": 40}]})"),
            "scene.json: /overlays/0/width_px: 40 is out of range 0.5..16 px");
}

TEST(SceneJson, EnumeratedValuesListTheChoices) {
  EXPECT_EQ(errorOf(R"({"radars": [{"path": "a.nc", "mode": "volume"}]})"),
            "scene.json: /radars/0/mode: \"volume\" is not one of \"dvr\", \"mip\", \"iso\"");
  EXPECT_EQ(errorOf(R"({"imagery": [{"type": "wms", "path": "x"}]})"),
            "scene.json: /imagery/0/type: \"wms\" is not one of \"pyramid\", \"xyz\"");
  const std::string colors = errorOf(R"({"radars": [{"path": "a.nc", "colors": "NWZ"}]})");
  EXPECT_EQ(colors.rfind("scene.json: /radars/0/colors: \"NWZ\" is neither a colour table (", 0), 0u) << colors;
  EXPECT_NE(colors.find("(did you mean \"nws\"?)"), std::string::npos) << colors;
}

TEST(SceneJson, MissingRequiredKeysAreNamed) {
  EXPECT_EQ(errorOf(R"({"radars": [{"field": "DBZ"}]})"),
            "scene.json: /radars/0: needs \"path\" (a radar file, directory, glob or comma list)");
  EXPECT_EQ(errorOf(R"({"markers": [{"lat_deg": 1}]})"), "scene.json: /markers/0: needs \"lon_deg\" (longitude, deg)");
  EXPECT_EQ(errorOf(R"({"grids": [{"path": ""}]})"), "scene.json: /grids/0/path: empty path");
}

TEST(SceneJson, LayersRememberTheirPointerForLoadErrors) {
  auto scene = engine::parseSceneJson(
      R"({"radars": [{"path": "a.nc"}, {"path": "b.nc"}, {"path": "c.nc"}], "grids": [{"path": "@data/g.nc"}],
          "overlays": [{"path": "o.geojson"}], "stations": "s.csv",
          "slices": [{"grid": "g.nc", "height_m": 3000}]})",
      "scene.json", "/base", "/data");
  ASSERT_TRUE(scene) << scene.error();
  ASSERT_EQ(scene->origins.volumes.size(), 4u);
  EXPECT_EQ(scene->origins.volumes[2], "scene.json: /radars/2");
  EXPECT_EQ(scene->volumes[2].path, "/base/c.nc");
  EXPECT_EQ(scene->volumes[2].kind, engine::VolumeKind::Radar);
  EXPECT_EQ(scene->origins.volumes.at(3), "scene.json: /grids/0");
  EXPECT_EQ(scene->volumes[3].path, "/data/g.nc");
  EXPECT_EQ(scene->volumes[3].kind, engine::VolumeKind::Grid);
  EXPECT_EQ(scene->origins.overlays.at(0), "scene.json: /overlays/0");
  EXPECT_EQ(scene->origins.slices.at(0), "scene.json: /slices/0");
  EXPECT_EQ(scene->origins.stations, "scene.json: /stations");
  EXPECT_EQ(engine::layerOrigin(scene->origins.volumes, 7, "--radar x"), "--radar x");
}

TEST(SceneJson, MissingInputFilesAreNamedWithTheirPointer) {
  const std::string missing = ATMOGLOBE_TEST_OUTPUT_DIR + "/no_such_radar.nc";
  auto st = engine::checkInputFile(missing, "scene.json: /radars/2/path");
  ASSERT_FALSE(st);
  EXPECT_EQ(st.error(), "scene.json: /radars/2/path: file not found: " + missing);
  EXPECT_TRUE(engine::checkInputFile(ATMOGLOBE_TEST_OUTPUT_DIR, "x"));            // exists
  EXPECT_TRUE(engine::checkInputFile(ATMOGLOBE_TEST_OUTPUT_DIR + "/*.h5", "x"));  // a glob: the reader says
  EXPECT_TRUE(engine::checkInputFile(missing + "," + missing + "2", "x"));        // a list: the reader says
}

// Every example scene shipped in assets/scenes/ parses (each is also rendered by the CLI test
// cli.scene_examples_*, which needs the generated data).
TEST(SceneJson, EveryExampleSceneParses) {
  const std::filesystem::path dir = std::filesystem::path(ATMOGLOBE_SOURCE_DIR) / "assets" / "scenes";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    auto scene = engine::loadSceneFile(entry.path().string(), "/data");
    EXPECT_TRUE(scene) << entry.path() << ": " << (scene ? "" : scene.error());
  }
  EXPECT_GE(count, 4) << "the schema document promises examples";
}

// An ensemble member is a grid's (and a grid slice's) choice: read as given, refused below 0 and
// on radars.
TEST(SceneJson, GridMemberIsReadAndRefusedWhereItMeansNothing) {
  auto scene = engine::parseSceneJson(
      R"({"grids": [{"path": "a.grib", "member": 7}, {"path": "b.grib"}],
          "slices": [{"grid": "a.grib", "member": 3, "height_m": 1000}]})",
      "scene.json", "/base", "/data");
  ASSERT_TRUE(scene) << scene.error();
  ASSERT_EQ(scene->volumes.size(), 2u);
  EXPECT_EQ(scene->volumes[0].member, 7);
  EXPECT_EQ(scene->volumes[1].member, -1);
  ASSERT_EQ(scene->slices.size(), 1u);
  EXPECT_EQ(scene->slices[0].source.member, 3);
  EXPECT_EQ(errorOf(R"({"grids": [{"path": "a.grib", "member": -2}]})"),
            "scene.json: /grids/0/member: -2 is out of range 0..1000000");
  EXPECT_NE(errorOf(R"({"radars": [{"path": "a.nc", "member": 1}]})").find("/radars/0/member: unknown key \"member\""),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"slices": [{"radar": "a.nc", "member": 1, "height_m": 1000}]})").find("member"),
            std::string::npos);
}

// `view`'s "Save scene" writes sceneToJson: read back, it describes the same scene. Every example
// scene and a scene using every key go through parse -> write -> parse -> write, and the two
// writings are the same text (so nothing the parser reads is lost or changed); the values that
// only the viewer produces (an edited opacity curve, the shown step) are checked one by one.
TEST(SceneJson, WrittenScenesReadBackTheSame) {
  auto roundTrip = [](const engine::SceneDescription& scene, const std::string& what) {
    const std::string once = engine::sceneToJson(scene);
    auto again = engine::parseSceneJson(once, what + " (written)", "/elsewhere", "/data");
    EXPECT_TRUE(again) << what << ": " << (again ? "" : again.error()) << "\n" << once;
    if (!again) return engine::SceneDescription{};
    EXPECT_EQ(engine::sceneToJson(*again), once) << what;
    return *again;
  };
  const std::filesystem::path dir = std::filesystem::path(ATMOGLOBE_SOURCE_DIR) / "assets" / "scenes";
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    auto scene = engine::loadSceneFile(entry.path().string(), "/data");
    ASSERT_TRUE(scene) << scene.error();
    roundTrip(*scene, entry.path().filename().string());
  }
  auto every = engine::parseSceneJson(R"({
    "camera": {"lat_deg": 35.1, "lon_deg": -97.3, "height_m": 123456.7, "heading_deg": 12.5, "pitch_deg": -33, "roll_deg": 2},
    "fov_deg": 41.5, "size": [640, 360], "vertical_exaggeration": 3, "memory_budget_mb": 512,
    "map_context": false, "range_rings": true,
    "imagery": [{"type": "xyz", "path": "tiles"}],
    "markers": [{"lat_deg": 35.3, "lon_deg": -97.5, "height_m": 400, "label": "OKC", "color": [0.1, 0.2, 0.3], "size_px": 9}],
    "stations": "sites.csv",
    "radars": [{"path": "ktlx.nc", "field": "VRADH", "colors": "velocity", "mode": "mip", "interpolation": "nearest",
                "step_m": 100, "image_scale": 0.5, "classification": "preintegrated", "iso_dbz": 35, "geoid": false,
                "beam": "straight", "label": "Twin Lakes", "range": [-30, 30], "opacity": [0, 20, 0.7, 500],
                "crop": [34, 36, -99, -96], "crop_heights_m": [0, 12000], "overlap": "lowest", "window_minutes": 6}],
    "grids": [{"path": "t.nc", "variable": "t", "time": "2001-01-01T06:00:00Z", "member": 3, "index": {"month": 2},
               "iso_value": 250.5, "opacity_points": [[200, 0], [250, 0.1], [300, 0.6]]}],
    "overlays": [{"path": "roads.geojson", "color": [1, 0, 0], "width_px": 2.5}],
    "slices": [{"grid": "t.nc", "variable": "t", "time": "1", "member": 3, "index": {"month": 2}, "height_m": 5000,
                "box": [30, 40, 170, -170], "datum": "ellipsoid", "colors": "turbo", "range": [200, 300],
                "opacity": 0.5, "resolution_px": 256, "geoid": false},
               {"radar": "ktlx.nc", "field": "DBZH", "path": [[35, -98], [35.5, -97]], "heights_m": [0, 15000]}],
    "surfaces": [{"path": "era5.grib", "variable": "z", "time": "2", "ensemble": "mean", "pressure_hpa": 500,
                  "colors": "turbo", "range": [48000, 58000], "opacity": 0.6, "fill": false, "contour_interval": 400,
                  "contour_color": [1, 1, 0], "contour_width_px": 2, "contour_labels": false, "geoid": false},
                 {"path": "msl.grib", "member": 4, "level": 2, "contour_values": [98000, 101300], "wind": "10u,10v",
                  "wind_color": [1, 1, 1]}]
  })",
                                      "every.json", "/base", "/data");
  ASSERT_TRUE(every) << every.error();
  const engine::SceneDescription back = roundTrip(*every, "every key");
  ASSERT_EQ(back.volumes.size(), 2u);
  EXPECT_EQ(back.volumes[0].path, "/base/ktlx.nc");  // written resolved, read back as it stands
  EXPECT_EQ(back.volumes[0].label, "Twin Lakes");
  EXPECT_EQ(back.volumes[0].settings.crop.topMeters, 12000.0);
  EXPECT_EQ(back.volumes[0].overlap, volume::OverlapRule::LowestBeam);
  EXPECT_EQ(back.volumes[0].windowMinutes, 6.0);
  const engine::VolumeLayerDescription& g = back.volumes[1];
  EXPECT_EQ(g.time, "2001-01-01T06:00:00Z");
  EXPECT_EQ(g.member, 3);
  EXPECT_EQ(g.gridIndex.at("month"), 2u);
  ASSERT_EQ(g.settings.opacityPoints.size(), 3u);
  EXPECT_EQ(g.settings.opacityPoints[1], glm::dvec2(250.0, 0.1));
  EXPECT_EQ(back.camera.heightMeters, 123456.7);
  EXPECT_EQ(back.camera.rollDeg, 2.0);
  ASSERT_EQ(back.slices.size(), 2u);
  EXPECT_EQ(back.slices[0].source.gridIndex.at("month"), 2u);
  EXPECT_EQ(back.slices[0].request.box->eastDeg, 190.0);  // over the antimeridian, as first read
  EXPECT_EQ(back.slices[1].request.path.size(), 2u);
  EXPECT_EQ(back.overlays.at(0).widthPx, 2.5f);
  EXPECT_FALSE(back.mapContext);
  ASSERT_EQ(back.surfaces.size(), 2u);
  EXPECT_EQ(back.surfaces[0].path, "/base/era5.grib");
  EXPECT_EQ(back.surfaces[0].pressureHpa, 500.0);
  EXPECT_EQ(back.surfaces[0].contourInterval, 400.0);
  EXPECT_FALSE(back.surfaces[0].fill);
  EXPECT_EQ(back.surfaces[0].ensemble, "mean");
  EXPECT_EQ(back.surfaces[1].member, 4);
  EXPECT_EQ(back.surfaces[1].wind, "10u,10v");
  EXPECT_EQ(back.surfaces[1].level, 2);
  EXPECT_EQ(back.surfaces[1].contourValues, (std::vector<double>{98000.0, 101300.0}));
  // A surface with a typo, and one with nothing to draw, are named.
  auto typo = engine::parseSceneJson(R"({"surfaces": [{"path": "a.grib", "contour_intervall": 4}]})", "s.json", "/base",
                                     "/data");
  ASSERT_FALSE(typo);
  EXPECT_NE(typo.error().find("s.json: /surfaces/0/contour_intervall: unknown key"), std::string::npos) << typo.error();
  auto nothing =
      engine::parseSceneJson(R"({"surfaces": [{"path": "a.grib", "fill": false}]})", "s.json", "/base", "/data");
  ASSERT_FALSE(nothing);
  EXPECT_NE(nothing.error().find("s.json: /surfaces/0: nothing to draw"), std::string::npos) << nothing.error();
  // An ensemble statistic on a grid and on a grid slice (not with a member).
  auto stats = engine::parseSceneJson(
      R"({"grids": [{"path": "t.nc", "ensemble": "prob:>=273.15"}],
          "slices": [{"grid": "t.nc", "ensemble": "spread", "height_m": 5000}]})",
      "stats.json", "/base", "/data");
  ASSERT_TRUE(stats) << stats.error();
  const engine::SceneDescription statsBack = roundTrip(*stats, "ensemble statistics");
  ASSERT_TRUE(statsBack.volumes.at(0).ensemble);
  EXPECT_EQ(volume::toString(*statsBack.volumes[0].ensemble), "prob:>=273.15");
  ASSERT_TRUE(statsBack.slices.at(0).source.ensemble);
  EXPECT_EQ(volume::toString(*statsBack.slices[0].source.ensemble), "spread");
  EXPECT_NE(errorOf(R"({"grids": [{"path": "t.nc", "member": 2, "ensemble": "mean"}]})").find("not with \"member\""),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"grids": [{"path": "t.nc", "ensemble": "median"}]})").find("expected mean, spread"),
            std::string::npos);
  // The overlap rule: the spellings; integrate (each radar of a network apart) is one of them.
  EXPECT_NE(errorOf(R"({"radars": [{"path": "k.nc", "overlap": "median"}]})").find("\"mean\""), std::string::npos)
      << errorOf(R"({"radars": [{"path": "k.nc", "overlap": "median"}]})");
  auto integrate = engine::parseSceneJson(R"({"radars": [{"path": "k.nc", "overlap": "integrate"}]})", "scene.json",
                                          "/base", "/data");
  ASSERT_TRUE(integrate) << integrate.error();
  EXPECT_EQ(integrate->volumes.at(0).overlap, volume::OverlapRule::Integrate);
  EXPECT_NE(errorOf(R"({"grids": [{"path": "t.nc", "overlap": "mean"}]})").find("overlap"), std::string::npos);
  // An edited curve must increase and stay in 0..1.
  EXPECT_NE(
      errorOf(R"({"grids": [{"path": "t.nc", "opacity_points": [[1, 0], [1, 0.5]]}]})").find("values must increase"),
      std::string::npos);
  EXPECT_NE(errorOf(R"({"grids": [{"path": "t.nc", "opacity_points": [[1, 0], [2, 1.5]]}]})").find("opacity in 0..1"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"grids": [{"path": "t.nc", "opacity_points": [[1, 0]]}]})").find("two or more"),
            std::string::npos);
}
