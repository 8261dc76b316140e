// Cone export: files pass the real validators (Khronos glTF validator, xmllint + COLLADA 1.4.1
// schema, unzip -t), georeference lands on the geolocated gates, writes are atomic.
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/AtomicFile.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/ConeExport.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/ZipArchive.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace atmoglobe;
using namespace atmoglobe::volume;
namespace fs = std::filesystem;

namespace {

const std::string kValidators = std::string(ATMOGLOBE_SOURCE_DIR) + "/tests/tools/validators";
const std::string kColladaSchema = "/usr/lib/opencollada/collada_schema_1_4_1.xsd";

fs::path outDir(const std::string& name) {
  const fs::path d = fs::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "cone-export" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Runs a shell command, returns (exit status, stdout+stderr).
std::pair<int, std::string> run(const std::string& cmd) {
  std::string out;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return {-1, "popen failed"};
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p)) out += buf.data();
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

// Fails (never skips) when the validator toolchain is missing, saying how to install it.
void requireValidators() {
  ASSERT_EQ(run("command -v node").first, 0) << "node not found: run scripts/install-deps.sh";
  ASSERT_TRUE(fs::exists(kValidators + "/node_modules/gltf-validator/package.json"))
      << "gltf-validator missing: run scripts/install-validators.sh";
  ASSERT_EQ(run("command -v xmllint").first, 0)
      << "xmllint not found: apt-get install libxml2-utils (scripts/install-deps.sh)";
  ASSERT_TRUE(fs::exists(kColladaSchema)) << kColladaSchema << " missing: apt-get install opencollada-tools";
  ASSERT_EQ(run("command -v unzip").first, 0) << "unzip not found: apt-get install unzip";
}

void expectGltfValid(const std::string& file) {
  const auto [rc, out] = run("node " + quote(kValidators + "/validate_gltf.js") + " " + quote(file));
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("errors=0"), std::string::npos) << out;
}

void expectColladaValid(const std::string& file) {
  const auto [rc, out] = run("XML_CATALOG_FILES=" + quote(kValidators + "/catalog.xml") +
                             " xmllint --noout --nonet --schema " + kColladaSchema + " " + quote(file));
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("validates"), std::string::npos) << out;
}

RadarVolume syntheticVolume() {
  RadarVolume v;
  v.format = "synthetic";
  v.sourcePath = "synthetic-volume";
  v.site.name = "TEST";
  v.site.latDeg = 35.3331;
  v.site.lonDeg = -97.2778;
  v.site.antennaHeightMeters = 390.0;
  v.site.heightDatum = HeightDatum::Ellipsoid;  // no geoid grid needed for the synthetic tests
  v.timeIso8601 = "2020-05-01T12:00:00Z";
  v.loadedField = {"DBZH", "dBZ", {}};
  for (double el : {0.5, 1.5, 4.0}) {
    Sweep s;
    s.indexInFile = static_cast<int>(v.sweeps.size());
    s.fixedAngleDeg = el;
    s.firstGateRangeMeters = 2125.0;
    s.gateSpacingMeters = 250.0;
    s.gateCount = 600;
    for (int i = 0; i < 360; ++i) {
      s.azimuthDeg.push_back(static_cast<float>(std::fmod(i + 0.5 + 0.1 * std::sin(i), 360.0)));
      s.elevationDeg.push_back(static_cast<float>(el));
      for (std::uint32_t g = 0; g < s.gateCount; ++g) {
        const double x = std::sin(i * 0.05) * 40.0 + std::cos(g * 0.02) * 30.0;
        s.values.push_back(g % 50 == 0 ? kNoData : (x < -20 ? kNoEcho : static_cast<float>(x)));
      }
    }
    v.sweeps.push_back(std::move(s));
  }
  return v;
}

ConeScene syntheticScene() {
  Result<ConeScene> scene = buildConeScene(syntheticVolume(), nwsReflectivityTable(), ConeExportOptions{});
  EXPECT_TRUE(scene.ok()) << scene.error();
  return std::move(scene.value());
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool noTemporaries(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp") != std::string::npos) return false;
  return true;
}

}  // namespace

TEST(ConeExport, GlbAndGltfPassKhronosValidator) {
  requireValidators();
  const fs::path dir = outDir("gltf");
  const ConeScene scene = syntheticScene();
  for (const char* name : {"cones.glb", "cones.gltf"}) {
    Result<std::vector<std::string>> files = exportCones(scene, (dir / name).string());
    ASSERT_TRUE(files.ok()) << files.error();
    expectGltfValid((dir / name).string());
  }
  ConeExportOptions straight;
  straight.mesh.straight = true;
  Result<ConeScene> s2 = buildConeScene(syntheticVolume(), cividisTable(-10, 70), straight);
  ASSERT_TRUE(s2.ok()) << s2.error();
  ASSERT_TRUE(exportCones(*s2, (dir / "straight.glb").string()).ok());
  expectGltfValid((dir / "straight.glb").string());
}

// The validator is a real check: a GLB with a broken accessor is reported with errors.
TEST(ConeExport, ValidatorRejectsBrokenGlb) {
  requireValidators();
  const fs::path dir = outDir("broken");
  std::string glb = encodeConesGltf(syntheticScene(), true, true);
  const std::size_t at = glb.find("\"count\":");
  ASSERT_NE(at, std::string::npos);
  glb.replace(at, 9, "\"count\":9");  // a wrong vertex count
  std::ofstream(dir / "broken.glb", std::ios::binary) << glb;
  const auto [rc, out] =
      run("node " + quote(kValidators + "/validate_gltf.js") + " " + quote((dir / "broken.glb").string()));
  EXPECT_NE(rc, 0) << out;
  EXPECT_EQ(out.find("errors=0"), std::string::npos) << out;
}

// Georeference: the root node matrix (double, column-major) maps the rim vertex at azimuth 0 of
// every sweep to a Y-up Earth-fixed world; rotating back by the 3D Tiles y-up -> z-up rule
// (x, y, z) -> (x, -z, y) gives ECEF within 1 m of geolocateGateExact for that gate.
TEST(ConeExport, GltfRootMatrixPutsConesOnTheGlobe) {
  const ConeScene scene = syntheticScene();
  const std::string glb = encodeConesGltf(scene, true, true);
  const std::uint32_t jsonLen = static_cast<std::uint8_t>(glb[12]) | (static_cast<std::uint8_t>(glb[13]) << 8) |
                                (static_cast<std::uint8_t>(glb[14]) << 16) |
                                (static_cast<std::uint32_t>(static_cast<std::uint8_t>(glb[15])) << 24);
  const nlohmann::json doc = nlohmann::json::parse(glb.substr(20, jsonLen));
  const nlohmann::json& root = doc["nodes"][doc["scenes"][0]["nodes"][0].get<int>()];
  ASSERT_TRUE(root.contains("matrix"));
  glm::dmat4 m;
  for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = root["matrix"][static_cast<std::size_t>(i)].get<double>();
  for (const Cone& cone : scene.cones) {
    std::size_t col = 0;
    for (std::size_t c = 0; c < cone.mesh.columnAzimuthDeg.size(); ++c)
      if (std::abs(std::remainder(cone.mesh.columnAzimuthDeg[c], 360.0)) < 1e-9) col = c;
    const glm::vec3 enu = cone.mesh.positionsEnu[cone.mesh.vertexIndex(col, cone.mesh.rowRangeMeters.size() - 1)];
    const glm::dvec4 local(enu.x, enu.z, -enu.y, 1.0);  // as stored in the glTF (Y-up)
    const glm::dvec4 yup = m * local;
    const glm::dvec3 ecef(yup.x, -yup.z, yup.y);
    const GatePosition gate =
        geolocateGateExact(scene.site.site, BeamModel{}, 0.0, cone.mesh.elevationDeg, cone.mesh.rowRangeMeters.back());
    EXPECT_LT(glm::length(ecef - gate.ecef), 1.0) << sweepStem(cone.sweepIndex);
  }
}

TEST(ConeExport, ColladaPassesSchema) {
  requireValidators();
  const fs::path dir = outDir("dae");
  const ConeScene scene = syntheticScene();
  Result<std::vector<std::string>> files = exportCones(scene, (dir / "cones.dae").string());
  ASSERT_TRUE(files.ok()) << files.error();
  expectColladaValid((dir / "cones.dae").string());
  for (const Cone& c : scene.cones) EXPECT_TRUE(fs::exists(dir / ("cones_" + sweepStem(c.sweepIndex) + ".png")));
  const std::string text = readFile(dir / "cones.dae");
  EXPECT_NE(text.find("<up_axis>Z_UP</up_axis>"), std::string::npos);
  EXPECT_NE(text.find("meter=\"1\""), std::string::npos);
  // The schema check is real: an element out of place fails it.
  std::string bad = text;
  bad.replace(bad.find("<up_axis>"), 9, "<upaxis>");
  bad.replace(bad.find("</up_axis>"), 10, "</upaxis>");
  std::ofstream(dir / "bad.dae") << bad;
  const auto [rc, out] =
      run("XML_CATALOG_FILES=" + quote(kValidators + "/catalog.xml") + " xmllint --noout --nonet --schema " +
          kColladaSchema + " " + quote((dir / "bad.dae").string()));
  EXPECT_NE(rc, 0) << out;
}

TEST(ConeExport, KmlModelsAtTheAntenna) {
  requireValidators();
  const fs::path dir = outDir("kml");
  const ConeScene scene = syntheticScene();
  Result<std::vector<std::string>> files = exportCones(scene, (dir / "cones.kml").string());
  ASSERT_TRUE(files.ok()) << files.error();
  const std::string kml = readFile(dir / "cones.kml");
  EXPECT_NE(kml.find("<altitudeMode>absolute</altitudeMode>"), std::string::npos);
  EXPECT_NE(kml.find("<longitude>-97.277800000</longitude><latitude>35.333100000</latitude>"), std::string::npos)
      << kml;
  // Ellipsoidal 390 m at this site: MSL altitude = 390 - N, N(EGM96) here is about -27 m, so
  // altitude about 417 m; only checked to be the geoid-corrected value, not the raw 390.
  EXPECT_EQ(kml.find("<altitude>390.000</altitude>"), std::string::npos);
  EXPECT_NE(kml.find("<heading>0</heading><tilt>0</tilt><roll>0</roll>"), std::string::npos);
  for (const Cone& c : scene.cones) {
    const fs::path dae = dir / "cones_files" / (sweepStem(c.sweepIndex) + ".dae");
    ASSERT_TRUE(fs::exists(dae));
    expectColladaValid(dae.string());
    EXPECT_LE(c.mesh.triangleCount(), static_cast<std::size_t>(kGoogleEarthMaxTrianglesPerModel));
  }
}

TEST(ConeExport, KmzUnzipsWithKmlModelsAndTextures) {
  requireValidators();
  const fs::path dir = outDir("kmz");
  const ConeScene scene = syntheticScene();
  Result<std::vector<std::string>> files = exportCones(scene, (dir / "cones.kmz").string());
  ASSERT_TRUE(files.ok()) << files.error();
  const std::string kmz = (dir / "cones.kmz").string();
  const auto [rc, out] = run("unzip -t " + quote(kmz));
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("No errors detected"), std::string::npos) << out;
  const auto [rcl, list] = run("unzip -l " + quote(kmz));
  EXPECT_EQ(rcl, 0);
  EXPECT_NE(list.find("doc.kml"), std::string::npos) << list;
  for (const Cone& c : scene.cones) {
    EXPECT_NE(list.find("models/" + sweepStem(c.sweepIndex) + ".dae"), std::string::npos) << list;
    EXPECT_NE(list.find("models/" + sweepStem(c.sweepIndex) + ".png"), std::string::npos) << list;
  }
  EXPECT_LT(list.find("doc.kml"), list.find("models/"));  // doc.kml first, as Google Earth expects
  EXPECT_TRUE(noTemporaries(dir));
  const auto [rcx, x] = run("cd " + quote(dir.string()) + " && unzip -o -q cones.kmz -d unpacked");
  ASSERT_EQ(rcx, 0) << x;
  expectColladaValid((dir / "unpacked" / "models" / "sweep00.dae").string());
  // The PNG inside is the one the scene holds, byte for byte.
  const std::string png = readFile(dir / "unpacked" / "models" / "sweep00.png");
  EXPECT_EQ(png, std::string(scene.cones[0].png.begin(), scene.cones[0].png.end()));
}

// The zip writer on its own, checked by Info-ZIP's unzip (an independent reader): contents come
// back byte for byte (binary with NULs, empty entry, nested name), deflate and store are what was
// asked for, and failures name the file and leave no temporary.
TEST(ConeExport, ZipArchiveReadsBackWithUnzip) {
  requireValidators();
  const fs::path dir = outDir("zip");
  std::string text;
  for (int i = 0; i < 2000; ++i) text += "<vertex>" + std::to_string(i) + "</vertex>\n";
  std::string binary;
  for (int i = 0; i < 70000; ++i) binary.push_back(static_cast<char>((i * 131) & 0xFF));  // NULs included
  const std::vector<ZipEntry> entries = {
      {"doc.kml", text, true}, {"models/data.bin", binary, false}, {"models/empty.txt", "", true}};
  const std::string zip = (dir / "a.kmz").string();
  ASSERT_TRUE(writeZipArchiveAtomic(zip, entries).ok());
  const auto [rc, out] = run("unzip -t " + quote(zip));
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("No errors detected"), std::string::npos) << out;
  // unzip -v: one line per entry with its method ("Defl:N" or "Stored") before the name.
  const auto [rcv, verbose] = run("unzip -v " + quote(zip));
  ASSERT_EQ(rcv, 0) << verbose;
  auto lineOf = [&](const std::string& name) {
    const std::size_t at = verbose.find(" " + name + "\n");
    if (at == std::string::npos) return std::string();
    return verbose.substr(verbose.rfind('\n', at) + 1, at - verbose.rfind('\n', at));
  };
  EXPECT_NE(lineOf("doc.kml").find("Defl"), std::string::npos) << verbose;
  EXPECT_NE(lineOf("models/data.bin").find("Stored"), std::string::npos) << verbose;
  EXPECT_LT(fs::file_size(zip), text.size() / 4 + binary.size() + 1000);  // the text did shrink
  const auto [rcx, x] = run("cd " + quote(dir.string()) + " && unzip -o -q a.kmz -d unpacked");
  ASSERT_EQ(rcx, 0) << x;
  EXPECT_EQ(readFile(dir / "unpacked" / "doc.kml"), text);
  EXPECT_EQ(readFile(dir / "unpacked" / "models" / "data.bin"), binary);
  EXPECT_EQ(readFile(dir / "unpacked" / "models" / "empty.txt"), "");

  // Replacing an existing archive works; a failed write leaves it as it was.
  ASSERT_TRUE(writeZipArchiveAtomic(zip, {{"only.txt", "second", true}}).ok());
  const std::string before = readFile(zip);
  const Status dup = writeZipArchiveAtomic(zip, {{"x.txt", "1", true}, {"x.txt", "2", true}});
  ASSERT_FALSE(dup.ok());
  EXPECT_NE(dup.error().find(zip), std::string::npos) << dup.error();
  EXPECT_EQ(readFile(zip), before);
  const std::string missing = (dir / "no-such-dir" / "b.kmz").string();
  const Status noDir = writeZipArchiveAtomic(missing, entries);
  ASSERT_FALSE(noDir.ok());
  EXPECT_NE(noDir.error().find(missing), std::string::npos) << noDir.error();
  const Status empty = writeZipArchiveAtomic((dir / "c.kmz").string(), {});
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().find("c.kmz"), std::string::npos) << empty.error();
  EXPECT_FALSE(fs::exists(dir / "c.kmz"));
  const Status isDir = writeZipArchiveAtomic((dir / "unpacked").string(), entries);
  ASSERT_FALSE(isDir.ok());
  EXPECT_NE(isDir.error().find("is a directory"), std::string::npos) << isDir.error();
  EXPECT_TRUE(noTemporaries(dir));
}

TEST(ConeExport, TilesetBesideGlb) {
  requireValidators();
  const fs::path dir = outDir("tiles");
  const ConeScene scene = syntheticScene();
  Result<std::vector<std::string>> files = exportConesTileset(scene, (dir / "tiles").string());
  ASSERT_TRUE(files.ok()) << files.error();
  expectGltfValid((dir / "tiles" / "cones.glb").string());
  const nlohmann::json t = nlohmann::json::parse(readFile(dir / "tiles" / "tileset.json"));
  EXPECT_EQ(t["root"]["content"]["uri"], "cones.glb");
  // The transform is ENU -> ECEF at the antenna: its translation is the antenna's ECEF position
  // (independent: geodeticToEcef of the site) and its third column the ellipsoid normal.
  const glm::dvec3 antenna = globe::geodeticToEcef(globe::Geodetic{35.3331, -97.2778, 390.0});
  EXPECT_NEAR(t["root"]["transform"][12].get<double>(), antenna.x, 1e-6);
  EXPECT_NEAR(t["root"]["transform"][13].get<double>(), antenna.y, 1e-6);
  EXPECT_NEAR(t["root"]["transform"][14].get<double>(), antenna.z, 1e-6);
  const glm::dvec3 up = globe::surfaceNormal(35.3331, -97.2778);
  EXPECT_NEAR(t["root"]["transform"][8].get<double>(), up.x, 1e-12);
  EXPECT_NEAR(t["root"]["transform"][10].get<double>(), up.z, 1e-12);
}

// An export to an unwritable place fails with a message naming the path and leaves nothing; a
// failing export over an existing good file leaves it untouched and no temporaries behind.
TEST(ConeExport, AtomicWriteLeavesGoodFileUntouched) {
  const fs::path dir = outDir("atomic");
  const ConeScene scene = syntheticScene();
  // Unwritable: /proc refuses new files even for root.
  Result<std::vector<std::string>> bad = exportCones(scene, "/proc/atmoglobe-cones-test.glb");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("/proc/atmoglobe-cones-test.glb"), std::string::npos) << bad.error();
  Result<std::vector<std::string>> missingDir = exportCones(scene, (dir / "no-such-dir" / "x.glb").string());
  ASSERT_FALSE(missingDir.ok());

  // A good .dae, then an export that fails half way: its PNG's path is a directory.
  const std::string good = (dir / "cones.dae").string();
  ASSERT_TRUE(exportCones(scene, good).ok());
  const std::string before = readFile(good);
  fs::remove(dir / "cones_sweep01.png");
  fs::create_directory(dir / "cones_sweep01.png");
  Result<std::vector<std::string>> failed = exportCones(scene, good);
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(failed.error().find("cones_sweep01.png"), std::string::npos) << failed.error();
  EXPECT_EQ(readFile(good), before);
  EXPECT_TRUE(noTemporaries(dir));

  // writeFileAtomic on its own: replaced on success, untouched on failure.
  const std::string f = (dir / "plain.txt").string();
  ASSERT_TRUE(writeFileAtomic(f, "first").ok());
  ASSERT_TRUE(writeFileAtomic(f, "second").ok());
  EXPECT_EQ(readFile(f), "second");
  EXPECT_FALSE(writeFileAtomic((dir / "missing" / "plain.txt").string(), "x").ok());
  EXPECT_TRUE(noTemporaries(dir));
}

TEST(ConeExport, BadInputIsAnError) {
  RadarVolume v = syntheticVolume();
  ConeExportOptions opt;
  opt.sweepIndices = {7};
  Result<ConeScene> r = buildConeScene(v, nwsReflectivityTable(), opt);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("sweep 7 out of range"), std::string::npos) << r.error();
  v.sweeps[1].values.clear();
  Result<ConeScene> r2 = buildConeScene(v, nwsReflectivityTable(), ConeExportOptions{});
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.error().find("sweep 1: field values not loaded"), std::string::npos) << r2.error();
  ConeExportOptions near;
  near.maxRangeMeters = 1000.0;  // below the first gate (2125 m)
  Result<ConeScene> r3 = buildConeScene(syntheticVolume(), nwsReflectivityTable(), near);
  ASSERT_FALSE(r3.ok());
  EXPECT_NE(r3.error().find("no gate within --max-range"), std::string::npos) << r3.error();
  EXPECT_FALSE(coneFormatFromPath("x.obj").ok());
}

// Real files: every reader's volume exports and validates.
TEST(ConeExport, RealVolumesValidate) {
  requireValidators();
  const fs::path dir = outDir("real");
  const std::string data = atmoglobe_test::testDataDir();
  const std::vector<std::string> paths = {data + "/radar_nexrad/KLBB20160601_150025_V06",
                                          data + "/radar_odim/40_20181220_060630.pvol.h5",
                                          data + "/radar_cfradial/example_plot_ppi_single_sweep.nc"};
  int k = 0;
  for (const std::string& p : paths) {
    SKIP_WITHOUT_TEST_DATA(p);
    Result<RadarVolume> vol = readRadarVolume(p, ReadOptions{});
    ASSERT_TRUE(vol.ok()) << vol.error();
    ConeExportOptions opt;
    opt.sweepIndices = {0};
    opt.maxRangeMeters = 150000.0;
    Result<ConeScene> scene = buildConeScene(*vol, nwsReflectivityTable(), opt);
    ASSERT_TRUE(scene.ok()) << scene.error();
    const std::string stem = "real" + std::to_string(k++);
    ASSERT_TRUE(exportCones(*scene, (dir / (stem + ".glb")).string()).ok());
    expectGltfValid((dir / (stem + ".glb")).string());
    ASSERT_TRUE(exportCones(*scene, (dir / (stem + ".dae")).string()).ok());
    expectColladaValid((dir / (stem + ".dae")).string());
  }
}
