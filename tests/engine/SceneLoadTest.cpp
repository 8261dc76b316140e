// Load only what the scene shows: a scene naming one field of a many-field
// radar file reads that field's data and no other field's; view culling of radars at load.
#include "GLTestUtil.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/ViewCulling.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Horizon.h>
#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <gtest/gtest.h>
#include <netcdf.h>
#include <map>

using namespace atmoglobe;

namespace {
const char* const kExtraFields[] = {"VEL", "ZDR", "RHOHV", "PHIDP", "KDP", "WIDTH"};

// A small SYNTHETIC CfRadial volume with six more (time, range) fields next to DBZ.
std::string manyFieldFile(std::size_t* raysTimesGates) {
  const std::string path = testutil::testOutputDir() + "/many_fields.nc";
  volume::SyntheticRadarOptions o;
  o.elevationsDeg = {0.5, 1.5, 3.0};
  o.raysPerSweep = 90;
  o.maxRangeMeters = 60000.0;
  volume::SyntheticRadarSummary summary;
  EXPECT_TRUE(volume::writeSyntheticCfRadial(path, o, &summary));
  int nc = -1, dTime = -1, dRange = -1;
  EXPECT_EQ(nc_open(path.c_str(), NC_WRITE, &nc), NC_NOERR);
  nc_inq_dimid(nc, "time", &dTime);
  nc_inq_dimid(nc, "range", &dRange);
  std::size_t nTime = 0, nRange = 0;
  nc_inq_dimlen(nc, dTime, &nTime);
  nc_inq_dimlen(nc, dRange, &nRange);
  nc_redef(nc);
  std::vector<int> vars;
  for (const char* name : kExtraFields) {
    int v = -1;
    const int dims[2] = {dTime, dRange};
    EXPECT_EQ(nc_def_var(nc, name, NC_SHORT, 2, dims, &v), NC_NOERR);
    const float scale = 0.01f, offset = 0.0f;
    nc_put_att_float(nc, v, "scale_factor", NC_FLOAT, 1, &scale);
    nc_put_att_float(nc, v, "add_offset", NC_FLOAT, 1, &offset);
    nc_put_att_text(nc, v, "units", 1, "1");
    vars.push_back(v);
  }
  EXPECT_EQ(nc_enddef(nc), NC_NOERR);
  std::vector<short> values(nTime * nRange);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<short>(i % 3000);
  for (int v : vars) EXPECT_EQ(nc_put_var_short(nc, v, values.data()), NC_NOERR);
  EXPECT_EQ(nc_close(nc), NC_NOERR);
  *raysTimesGates = nTime * nRange;
  return path;
}
}  // namespace

TEST(SceneLoad, OneFieldOfAManyFieldFileReadsOnlyThatField) {
  testutil::glContext();
  std::size_t gates = 0;
  const std::string path = manyFieldFile(&gates);
  auto scene =
      engine::parseSceneJson(R"({"radars": [{"path": ")" + path + R"(", "field": "ZDR"}]})", "test scene", "", "");
  ASSERT_TRUE(scene) << scene.error();
  auto loader = engine::openImagery({}, {});
  ASSERT_TRUE(loader) << loader.error();
  auto renderer = engine::SceneRendererGL::create(*loader);
  ASSERT_TRUE(renderer) << renderer.error();
  io::resetNetcdfReadTally();
  auto layer = (*renderer)->addVolume(engine::volumesOfKind(*scene, engine::VolumeKind::Radar).at(0));
  ASSERT_TRUE(layer) << layer.error();
  EXPECT_EQ(testutil::polarOf(*layer).fieldName, "ZDR");
  // Variable names as NetcdfFile gives them: full paths ("/ZDR"); compared without the root.
  std::map<std::string, std::uint64_t> tally;
  for (const auto& [name, bytes] : io::netcdfReadTally())
    tally[name.rfind('/', 0) == 0 ? name.substr(1) : name] += bytes;
  // The field named: every gate once, 2 bytes each (short), no more (no second pass, no other
  // sweep's rays twice).
  ASSERT_TRUE(tally.count("ZDR")) << "the named field was not read through NetcdfFile";
  EXPECT_EQ(tally.at("ZDR"), gates * sizeof(short));
  // No other field: not one byte of their data.
  for (const char* other : {"DBZ", "VEL", "RHOHV", "PHIDP", "KDP", "WIDTH"})
    EXPECT_EQ(tally.count(other) ? tally.at(other) : 0u, 0u) << other << " was read";
  // The rest is coordinates and metadata: far below one more field (the 3 sweeps' azimuths,
  // elevations, times in doubles are 3 x 8 bytes per ray against 2 bytes x 240 gates per ray).
  std::uint64_t others = 0;
  for (const auto& [name, bytes] : tally)
    if (name != "ZDR") others += bytes;
  EXPECT_LT(others, gates * sizeof(short) / 2) << "coordinates and metadata read";
}

TEST(SceneLoad, RadarsOutsideTheViewAreNotLoaded) {
  // Two SYNTHETIC volumes: one at KTLX (the synthetic default site), one at KLIX (New Orleans,
  // ~900 km away).
  const std::string near = testutil::testOutputDir() + "/cull_ktlx.nc",
                    far = testutil::testOutputDir() + "/cull_klix.nc";
  volume::SyntheticRadarOptions o;
  o.elevationsDeg = {0.5, 2.0};
  o.raysPerSweep = 36;
  ASSERT_TRUE(volume::writeSyntheticCfRadial(near, o));
  o.siteId = "KLIX", o.siteLatDeg = 30.3367, o.siteLonDeg = -89.8256, o.antennaAltitudeMslMeters = 38.0;
  ASSERT_TRUE(volume::writeSyntheticCfRadial(far, o));
  engine::SceneDescription scene;
  scene.volumes.push_back({});
  scene.volumes.back().path = near;
  scene.volumes.push_back({});
  scene.volumes.back().path = far;
  // Regional: 400 km above KTLX looking down, 45 deg field of view (~330 km across): KLIX's
  // 230 km volume ends ~670 km from the view's edge.
  {
    engine::SceneDescription s = scene;
    const engine::Camera regional({35.33, -97.28, 4e5, 0, -90, 0}, 45.0, 640, 360);
    const auto out = engine::cullRadarsOutsideView(s, regional);
    EXPECT_EQ(out.kept, 1u);
    ASSERT_EQ(out.culled.size(), 1u);
    EXPECT_EQ(out.culled[0], far);
    ASSERT_EQ(s.volumes.size(), 1u);
    EXPECT_EQ(s.volumes[0].path, near);
  }
  // The whole globe over North America: both stay.
  {
    engine::SceneDescription s = scene;
    const engine::Camera globe({35.0, -95.0, 1.5e7, 0, -90, 0}, 45.0, 640, 360);
    EXPECT_EQ(engine::cullRadarsOutsideView(s, globe).kept, 2u);
  }
  // The whole globe from the other side (over the Indian Ocean): both behind the Earth.
  {
    engine::SceneDescription s = scene;
    const engine::Camera other({-30.0, 85.0, 1.5e7, 0, -90, 0}, 45.0, 640, 360);
    EXPECT_EQ(engine::cullRadarsOutsideView(s, other).kept, 0u);
  }
  // Just outside the view: the camera over a point 300 km west of KLIX's volume edge sees it
  // once the view is wide enough to reach it (the sphere test is not a fixed distance rule).
  {
    engine::SceneDescription s = scene;
    s.volumes.erase(s.volumes.begin());
    const engine::Camera narrow({30.34, -96.0, 4e5, 0, -90, 0}, 30.0, 640, 640);
    const engine::Camera wide({30.34, -96.0, 4e5, 0, -90, 0}, 120.0, 640, 640);
    engine::SceneDescription s2 = s;
    EXPECT_EQ(engine::cullRadarsOutsideView(s, narrow).kept, 0u);
    EXPECT_EQ(engine::cullRadarsOutsideView(s2, wide).kept, 1u);
  }
}

TEST(SceneLoad, SphereVisibilityIsConservativeForEveryPixelOfAVisiblePoint) {
  // A small sphere around points sampled on the ground under random cameras: if any of those
  // points projects into the image and is not behind the ellipsoid, the sphere must be kept.
  const engine::Camera camera({40.0, -100.0, 2e6, 30, -60, 0}, 60.0, 800, 450);
  int kept = 0, culled = 0;
  for (int i = 0; i < 2000; ++i) {
    const double lat = -80.0 + 160.0 * ((i * 37) % 2000) / 2000.0, lon = -180.0 + 360.0 * ((i * 91) % 2000) / 2000.0;
    const glm::dvec3 p = globe::geodeticToEcef({lat, lon, 1000.0});
    const auto px = camera.projectToPixel(p);
    const bool seen = px && px->x >= 0 && px->y >= 0 && px->x <= 800 && px->y <= 450 &&
                      !globe::isOccludedByEllipsoid(camera.eyeEcef(), p);
    const bool mayBe = engine::sphereMayBeVisible(camera, {p, 10.0});
    if (seen) {
      EXPECT_TRUE(mayBe) << lat << " " << lon;
    }
    (mayBe ? kept : culled)++;
  }
  EXPECT_GT(culled, 1000);  // most of the globe is out of this view: the test is not vacuous
  EXPECT_GT(kept, 20);
}
