// GRIB model levels: hybrid levels (IFS: the `pv` coefficients, sp or lnsp, the hydrostatic
// integration from the surface geopotential) and ICON/COSMO's generalised vertical levels (the
// half-level heights HHL). The files are written here with ecCodes (a small regular_ll grid,
// values packed as 64-bit IEEE so that what is read is exactly what was written), and every
// expected pressure and height is computed here by hand from what was written, not by the reader
// under test. The sparse IFS sample of ../shared (GribModelLevelsReal) shows the approximate path.
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <eccodes.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

using namespace atmoglobe::volume;

namespace {

// The grid of every file written: 4 x 3 points, 1 degree, rows north to south (46, 45, 44 N),
// columns 6 .. 9 E.
constexpr long kNi = 4, kNj = 3;
constexpr std::size_t kPoints = static_cast<std::size_t>(kNi * kNj);
double latOfRow(std::size_t fileRow) { return 46.0 - static_cast<double>(fileRow); }
double lonOfColumn(std::size_t fileCol) { return 6.0 + static_cast<double>(fileCol); }

/// One GRIB2 message to write.
struct Message {
  std::string shortName;    ///< for hybrid and surface messages
  std::string typeOfLevel;  ///< hybrid, surface, generalVertical, generalVerticalLayer
  long level = 0;
  std::vector<double> values;  ///< kNj x kNi, file order (row 0 = 46 N); NaN: missing (bitmap)
  std::vector<double> pv;      ///< hybrid: a then b; generalVertical: the 6 values of ICON's grid descriptor
  long dataTime = 1200;
  long category = -1, number = -1;  ///< generalVertical: parameterCategory / parameterNumber (discipline 0)

  Message(std::string name, std::string type, long lev, std::vector<double> v, std::vector<double> coefficients,
          long time = 1200, long cat = -1, long num = -1)
      : shortName(std::move(name)), typeOfLevel(std::move(type)), level(lev), values(std::move(v)),
        pv(std::move(coefficients)), dataTime(time), category(cat), number(num) {}
};

/// Appends `m` to `f`; returns its length in bytes (0: ecCodes failed).
std::size_t writeMessage(FILE* f, const Message& m) {
  std::unique_ptr<codes_handle, decltype(&codes_handle_delete)> h(
      codes_grib_handle_new_from_samples(nullptr, "regular_ll_sfc_grib2"), &codes_handle_delete);
  if (!h) return 0;
  codes_handle* g = h.get();
  int err = 0;
  auto setLong = [&](const char* key, long v) { err |= codes_set_long(g, key, v); };
  auto setDouble = [&](const char* key, double v) { err |= codes_set_double(g, key, v); };
  setLong("dataDate", 20240115);
  setLong("dataTime", m.dataTime);
  setLong("Ni", kNi);
  setLong("Nj", kNj);
  setDouble("latitudeOfFirstGridPointInDegrees", latOfRow(0));
  setDouble("longitudeOfFirstGridPointInDegrees", lonOfColumn(0));
  setDouble("latitudeOfLastGridPointInDegrees", latOfRow(kNj - 1));
  setDouble("longitudeOfLastGridPointInDegrees", lonOfColumn(kNi - 1));
  setDouble("iDirectionIncrementInDegrees", 1.0);
  setDouble("jDirectionIncrementInDegrees", 1.0);
  if (m.typeOfLevel == "generalVertical" || m.typeOfLevel == "generalVerticalLayer") {
    // ICON's layout (DWD, centre 78): first fixed surface 150 (generalised vertical), the level
    // number; HHL's second surface is mean sea level (101), a layer's the level below (150, k+1).
    // The grid descriptor goes in as the 6 pv values first (ecCodes reads them back as nlev,
    // numberOfVGridUsed and uuidOfVGrid once the surface type is 150).
    setLong("PVPresent", 1);
    err |= codes_set_double_array(g, "pv", m.pv.data(), m.pv.size());
    setLong("centre", 78);
    setLong("discipline", 0);
    setLong("parameterCategory", m.category);
    setLong("parameterNumber", m.number);
    // Both surface types first: setting a type clears the surfaces' values.
    setLong("typeOfFirstFixedSurface", 150);
    if (m.shortName == "HHL") setLong("typeOfSecondFixedSurface", 101);
    if (m.typeOfLevel == "generalVerticalLayer") setLong("typeOfSecondFixedSurface", 150);
    setLong("scaleFactorOfFirstFixedSurface", 0);
    setLong("scaledValueOfFirstFixedSurface", m.level);
    if (m.typeOfLevel == "generalVerticalLayer") {
      setLong("scaleFactorOfSecondFixedSurface", 0);
      setLong("scaledValueOfSecondFixedSurface", m.level + 1);
    }
  } else {
    std::size_t len = m.typeOfLevel.size();
    err |= codes_set_string(g, "typeOfLevel", m.typeOfLevel.c_str(), &len);
    setLong("level", m.level);
    if (!m.pv.empty()) {
      setLong("PVPresent", 1);
      err |= codes_set_double_array(g, "pv", m.pv.data(), m.pv.size());
    }
    len = m.shortName.size();
    err |= codes_set_string(g, "shortName", m.shortName.c_str(), &len);
  }
  std::size_t len = 9;
  err |= codes_set_string(g, "packingType", "grid_ieee", &len);
  setLong("precision", 2);  // 64-bit IEEE: exact
  std::vector<double> values = m.values;
  bool missing = false;
  for (double& x : values)
    if (std::isnan(x)) {
      x = 9999.0;
      missing = true;
    }
  if (missing) {
    setLong("bitmapPresent", 1);
    setDouble("missingValue", 9999.0);
  }
  err |= codes_set_double_array(g, "values", values.data(), values.size());
  const void* bytes = nullptr;
  std::size_t size = 0;
  err |= codes_get_message(g, &bytes, &size);
  if (err != 0) return 0;
  return std::fwrite(bytes, 1, size, f) == size ? size : 0;
}

/// Writes `messages` to `path`; the length of each (0 where ecCodes failed).
std::vector<std::size_t> writeGrib(const std::string& path, const std::vector<Message>& messages) {
  std::vector<std::size_t> sizes;
  std::unique_ptr<FILE, decltype(&std::fclose)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
  for (const Message& m : messages) sizes.push_back(f ? writeMessage(f.get(), m) : 0);
  return sizes;
}

std::string useTestCache() {
  const std::string dir = atmoglobe_test::freshTestDir("grib_cache");
  setenv("ATMOGLOBE_CACHE_DIR", dir.c_str(), 1);
  return dir;
}

// ---------------------------------------------------------------- the hybrid column of the tests

/// 10 model levels: half-level a (Pa) and b, from the top (half level 1/2) to the surface (10 1/2).
const std::vector<double> kA = {0, 2000, 4000, 6000, 8000, 9000, 8000, 6000, 3500, 1000, 0};
const std::vector<double> kB = {0, 0, 0, 0.02, 0.08, 0.18, 0.32, 0.5, 0.7, 0.88, 1};
constexpr std::size_t kLevels = 10;

std::vector<double> pvOf(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> pv = a;
  pv.insert(pv.end(), b.begin(), b.end());
  return pv;
}

/// The made-up atmosphere, per point (file order): surface geopotential (m2 s-2), surface
/// pressure (Pa), temperature (K) and specific humidity (kg/kg) of model level k (1 .. 10).
double surfaceGeopotential(std::size_t p) { return 2500.0 * static_cast<double>(p); }  // 0 .. 2.8 km
double surfacePressure(std::size_t p) { return 101000.0 * std::exp(-surfaceGeopotential(p) / (287.0 * 280.0)); }
double halfPressure(std::size_t i, double ps) { return kA[i] + kB[i] * ps; }
double temperature(std::size_t k, std::size_t p) {
  const double pFull = 0.5 * (halfPressure(k - 1, surfacePressure(p)) + halfPressure(k, surfacePressure(p)));
  return std::max(210.0, 300.0 - 0.4 * static_cast<double>(p) - 45.0 * std::log(101325.0 / pFull));
}
double humidity(std::size_t k, std::size_t p) {
  return 0.012 * std::pow(halfPressure(k, surfacePressure(p)) / surfacePressure(p), 3.0) +
         0.0005 * static_cast<double>(p % 3);
}

std::vector<double> field(const std::function<double(std::size_t)>& f) {
  std::vector<double> v(kPoints);
  for (std::size_t p = 0; p < kPoints; ++p) v[p] = f(p);
  return v;
}

/// The messages of a full IFS-like model-level file: lnsp and z on model level 1, t and q on
/// every level.
std::vector<Message> ifsMessages(const std::vector<double>& pv) {
  std::vector<Message> m;
  m.push_back({"lnsp", "hybrid", 1, field([](std::size_t p) { return std::log(surfacePressure(p)); }), pv});
  m.push_back({"z", "hybrid", 1, field(surfaceGeopotential), pv});
  for (std::size_t k = 1; k <= kLevels; ++k) {
    m.push_back({"t", "hybrid", static_cast<long>(k), field([k](std::size_t p) { return temperature(k, p); }), pv});
    m.push_back({"q", "hybrid", static_cast<long>(k), field([k](std::size_t p) { return humidity(k, p); }), pv});
  }
  return m;
}

/// By hand, IFS's rule written out (REFERENCE.md section 10; IFS documentation Part III): the
/// full-level geopotential (m2 s-2) of model levels 1 .. 10 at point p, summing each level's
/// layer thickness Rd Tv ln(p(j+1/2) / p(j-1/2)) from the surface up to the half level below
/// level k, then alpha(k) Rd Tv(k) into the level (alpha = ln 2 at the top level).
std::vector<double> handGeopotential(std::size_t p, bool moist, double phiSurface) {
  const double rd = 287.06, ps = surfacePressure(p);
  auto tv = [&](std::size_t j) { return temperature(j, p) * (1.0 + (moist ? 0.609133 * humidity(j, p) : 0.0)); };
  std::vector<double> phi(kLevels + 1);
  for (std::size_t k = 1; k <= kLevels; ++k) {
    double below = phiSurface;  // geopotential of half level k + 1/2
    for (std::size_t j = k + 1; j <= kLevels; ++j)
      below += rd * tv(j) * std::log(halfPressure(j, ps) / halfPressure(j - 1, ps));
    const double pAbove = halfPressure(k - 1, ps), pBelow = halfPressure(k, ps);
    const double alpha = k == 1 ? std::log(2.0) : 1.0 - pAbove / (pBelow - pAbove) * std::log(pBelow / pAbove);
    phi[k] = below + alpha * rd * tv(k);
  }
  return phi;
}

/// Geopotential -> height above the WGS84 ellipsoid at point p: / g0, geometric height (WGS84
/// normal gravity, the public VerticalCoordinate.h function), + EGM96.
double ellipsoidHeight(double phi, std::size_t p) {
  const double lat = latOfRow(p / kNi), lon = lonOfColumn(p % kNi);
  const auto& geoid = defaultEgm96Grid();
  return geometricFromGeopotentialHeightMeters(phi / 9.80665, lat) +
         (geoid.ok() ? geoid->undulationMeters(lat, lon) : 0);
}

/// Output (k, j, i) of model level `level` and file point p of a volume read whole.
std::size_t outIndex(const GridVolume& g, std::size_t level, std::size_t p) {
  const std::size_t k = kLevels - level;                 // bottom first
  const std::size_t j = kNj - 1 - p / kNi, i = p % kNi;  // rows turned south to north
  return g.index(k, j, i);
}

GridReadOptions options(const std::string& variable, bool useGeoid = true) {
  GridReadOptions o;
  o.variable = variable;
  o.useGeoid = useGeoid;
  return o;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST(GribModelLevels, HybridColumnMatchesAHandComputedHydrostaticColumn) {
  ASSERT_TRUE(defaultEgm96Grid().ok()) << defaultEgm96Grid().error();
  useTestCache();
  const std::string file = atmoglobe_test::freshTestDir("grib_hybrid") + "/ifs_ml.grib2";
  std::vector<Message> messages = ifsMessages(pvOf(kA, kB));
  // A later t at the bottom level: another time step, never read for this one.
  messages.push_back({"t", "hybrid", 10, field([](std::size_t) { return 280.0; }), pvOf(kA, kB), 1800});
  const auto sizes = writeGrib(file, messages);
  for (std::size_t s : sizes) ASSERT_GT(s, 0u);

  GridReadOptions o;
  o.variable = "t";
  auto g = readGridVolume(file, o);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->variable, "t:hybrid");
  EXPECT_EQ(g->verticalKind, VerticalKind::HybridSigmaPressure);
  EXPECT_EQ(g->heightSource, HeightSource::HydrostaticIntegration);
  EXPECT_FALSE(g->approximateHeights) << g->heightNote;
  EXPECT_TRUE(contains(g->heightNote, "exp('lnsp:hybrid' on model level 1)")) << g->heightNote;
  EXPECT_TRUE(contains(g->heightNote, "'z:hybrid' on model level 1")) << g->heightNote;
  EXPECT_TRUE(contains(g->heightNote, "Tv = T (1 + 0.609133 q) of 't:hybrid' and 'q:hybrid'")) << g->heightNote;
  ASSERT_EQ(g->nz, kLevels);
  ASSERT_EQ(g->nx, 4u);
  ASSERT_EQ(g->ny, 3u);
  EXPECT_EQ(g->levelValues, (std::vector<double>{10, 9, 8, 7, 6, 5, 4, 3, 2, 1}));
  EXPECT_EQ(g->levelUnits, "model level (1 = top)");
  EXPECT_EQ(g->times.size(), 2u);
  // Every message but the later t, each once (t decoded for its values and for the heights).
  std::uint64_t expected = 0;
  for (std::size_t i = 0; i + 1 < sizes.size(); ++i) expected += sizes[i];
  EXPECT_EQ(g->bytesRead, expected);

  // Every column against the hand computation. Float storage of the heights: 2 mm at 30 km;
  // the sums in double differ in rounding only (1e-9 m): 0.01 m.
  double maxDiff = 0;
  for (std::size_t p = 0; p < kPoints; ++p) {
    ASSERT_NEAR(g->latDeg[kNj - 1 - p / kNi], latOfRow(p / kNi), 1e-9);
    const auto phi = handGeopotential(p, true, surfaceGeopotential(p));
    for (std::size_t level = 1; level <= kLevels; ++level) {
      const double h = ellipsoidHeight(phi[level], p);
      ASSERT_NEAR(g->heightAboveEllipsoidMeters[outIndex(*g, level, p)], h, 0.01)
          << "point " << p << " level " << level;
      maxDiff = std::max(maxDiff, std::fabs(g->heightAboveEllipsoidMeters[outIndex(*g, level, p)] - h));
      ASSERT_EQ(g->values[outIndex(*g, level, p)], static_cast<float>(temperature(level, p)));
    }
  }
  std::printf("hydrostatic column: max |reader - hand| = %.4f m\n", maxDiff);
  // The bottom level of the column at sea level lies about 500 m up, the top (10 hPa) near 30 km
  // (column 0 at 46 N 6 E: EGM96 about 50 m; level 10 at ~95 kPa).
  EXPECT_NEAR(g->heightAboveEllipsoidMeters[outIndex(*g, 10, 0)], 550.0, 100.0);
  EXPECT_NEAR(g->heightAboveEllipsoidMeters[outIndex(*g, 1, 0)], 31000.0, 2500.0);

  // A crop of levels 8 .. 6 integrates from the bottom just the same, reading t and q up to level 6 only.
  GridReadOptions crop = o;
  crop.crop.firstLevel = 2;
  crop.crop.levelCount = 3;
  auto c = readGridVolume(file, crop);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->levelValues, (std::vector<double>{8, 7, 6}));
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t col = 0; col < kPoints; ++col)
      ASSERT_EQ(c->heightAboveEllipsoidMeters[k * kPoints + col],
                g->heightAboveEllipsoidMeters[(k + 2) * kPoints + col]);
  std::uint64_t cropBytes = sizes[0] + sizes[1];  // lnsp, z
  for (std::size_t level = 6; level <= kLevels; ++level) cropBytes += sizes[2 * level] + sizes[2 * level + 1];
  EXPECT_EQ(c->bytesRead, cropBytes);

  // Each value's pressure, kept when asked (isobaric surfaces): the mean of the half levels
  // around it, a + b ps. ps comes back through GRIB's packing of lnsp; the difference printed.
  EXPECT_TRUE(g->pressurePa.empty());
  GridReadOptions keep = o;
  keep.keepPressure = true;
  auto kp = readGridVolume(file, keep);
  ASSERT_TRUE(kp.ok()) << kp.error();
  ASSERT_EQ(kp->pressurePa.size(), kp->values.size());
  double maxPressureDiff = 0;
  for (std::size_t p = 0; p < kPoints; ++p)
    for (std::size_t level = 1; level <= kLevels; ++level) {
      const double expectedPa =
          0.5 * (halfPressure(level - 1, surfacePressure(p)) + halfPressure(level, surfacePressure(p)));
      maxPressureDiff = std::max(maxPressureDiff, std::fabs(kp->pressurePa[outIndex(*kp, level, p)] - expectedPa));
    }
  std::printf("hybrid pressures: max |reader - hand| = %.4f Pa\n", maxPressureDiff);
  // lnsp packed to 16 bits over its span across the points (about 0.1): 2e-6 in ln p, 0.2 Pa at
  // 1000 hPa; the float storage 0.008 Pa.
  EXPECT_LT(maxPressureDiff, 1.0);

  // info: the vertical kind, the source and (not) approximate, in text and JSON.
  auto info = describeGridFile(file, "t:hybrid");
  ASSERT_TRUE(info.ok()) << info.error();
  const std::string text = describeGridText(*info);
  EXPECT_TRUE(contains(text,
                       "vertical:   hybrid sigma-pressure (hybrid), 10 levels, heights from hydrostatic "
                       "integration\n"))
      << text;
  const std::string json = describeGridJson(*info);
  EXPECT_TRUE(contains(json, "\"kind\": \"hybrid sigma-pressure\"")) << json;
  EXPECT_TRUE(contains(json, "\"height_source\": \"hydrostatic integration\"")) << json;
  EXPECT_TRUE(contains(json, "\"approximate\": false")) << json;
  // lnsp and z on model level 1 are listed, not offered as volumes.
  for (const auto& v : info->variables)
    if (v.name == "lnsp:hybrid" || v.name == "z:hybrid") {
      EXPECT_FALSE(v.onGrid) << v.name;
      EXPECT_TRUE(contains(v.notReadable, "it is no 3-D field")) << v.notReadable;
    }
  auto lnsp = readGridVolume(file, options("lnsp"));
  ASSERT_FALSE(lnsp.ok());
  EXPECT_TRUE(contains(lnsp.error(), "lnsp:hybrid: the log of the surface pressure")) << lnsp.error();
}

TEST(GribModelLevels, SurfacePressureOrographyAndDryAir) {
  // sp on the surface instead of lnsp, orog (m) instead of z, no q: Tv = T.
  ASSERT_TRUE(defaultEgm96Grid().ok());
  useTestCache();
  const std::string file = atmoglobe_test::freshTestDir("grib_hybrid") + "/sp_orog.grib2";
  const std::vector<double> pv = pvOf(kA, kB);
  // Orography (m) whose geopotential is the test's surface geopotential: by bisection on the
  // public geopotential -> geometric conversion.
  auto orography = [](std::size_t p) {
    const double h = surfaceGeopotential(p) / 9.80665;
    return geometricFromGeopotentialHeightMeters(h, latOfRow(p / kNi));
  };
  std::vector<Message> m = {{"sp", "surface", 0, field(surfacePressure), {}},
                            {"orog", "surface", 0, field(orography), {}}};
  for (std::size_t k = 1; k <= kLevels; ++k)
    m.push_back({"t", "hybrid", static_cast<long>(k), field([k](std::size_t p) { return temperature(k, p); }), pv});
  for (std::size_t s : writeGrib(file, m)) ASSERT_GT(s, 0u);
  auto g = readGridVolume(file);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->variable, "t:hybrid");
  EXPECT_EQ(g->heightSource, HeightSource::HydrostaticIntegration);
  EXPECT_FALSE(g->approximateHeights);
  EXPECT_TRUE(contains(g->heightNote, "ps = 'sp:surface'")) << g->heightNote;
  EXPECT_TRUE(contains(g->heightNote, "'orog:surface' (m, as geopotential)")) << g->heightNote;
  EXPECT_TRUE(contains(g->heightNote, "Tv = T of 't:hybrid' (no q")) << g->heightNote;
  for (std::size_t p = 0; p < kPoints; ++p) {
    const auto phi = handGeopotential(p, false, surfaceGeopotential(p));
    // orog -> geopotential is inverted by the reader to well below 1 mm.
    for (std::size_t level = 1; level <= kLevels; ++level)
      ASSERT_NEAR(g->heightAboveEllipsoidMeters[outIndex(*g, level, p)], ellipsoidHeight(phi[level], p), 0.01)
          << "point " << p << " level " << level;
  }
}

TEST(GribModelLevels, PressuresFromPvAndApproximateHeightsWithoutTheSurfaceGeopotential) {
  // lnsp, t and q but no surface geopotential: pressures a + b ps per column, heights by the
  // standard atmosphere of those pressures, approximate. The heights are a check of the pressures.
  ASSERT_TRUE(defaultEgm96Grid().ok());
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_hybrid");
  std::vector<Message> all = ifsMessages(pvOf(kA, kB));
  std::vector<Message> noZ;
  for (const Message& m : all)
    if (m.shortName != "z") noZ.push_back(m);
  for (std::size_t s : writeGrib(dir + "/no_z.grib2", noZ)) ASSERT_GT(s, 0u);
  for (std::size_t s : writeGrib(dir + "/full.grib2", all)) ASSERT_GT(s, 0u);
  auto g = readGridVolume(dir + "/no_z.grib2", options("t"));
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_TRUE(g->approximateHeights);
  EXPECT_EQ(g->heightSource, HeightSource::StandardAtmosphere);
  EXPECT_EQ(g->verticalKind, VerticalKind::HybridSigmaPressure);
  EXPECT_TRUE(contains(g->heightNote,
                       "APPROXIMATE: not integrated hydrostatically, the file lacks the surface "
                       "geopotential (z on model level 1 or on the surface, or orog)"))
      << g->heightNote;
  EXPECT_FALSE(contains(g->heightNote, "surface pressure")) << g->heightNote;
  for (std::size_t p = 0; p < kPoints; ++p)
    for (std::size_t level = 1; level <= kLevels; ++level) {
      const double ps = surfacePressure(p);
      const double pFull = 0.5 * (halfPressure(level - 1, ps) + halfPressure(level, ps));
      const double h = ellipsoidHeight(9.80665 * standardAtmosphereGeopotentialHeightMeters(pFull), p);
      ASSERT_NEAR(g->heightAboveEllipsoidMeters[outIndex(*g, level, p)], h, 0.01) << p << " " << level;
    }
  // How far the standard atmosphere is from the hydrostatic heights of the same file with z.
  auto full = readGridVolume(dir + "/full.grib2", options("t"));
  ASSERT_TRUE(full.ok()) << full.error();
  double worst = 0;
  for (std::size_t i = 0; i < g->heightAboveEllipsoidMeters.size(); ++i)
    worst = std::max(
        worst, static_cast<double>(std::fabs(g->heightAboveEllipsoidMeters[i] - full->heightAboveEllipsoidMeters[i])));
  std::printf("approximate (standard atmosphere) vs hydrostatic: max |difference| = %.1f m; column 0 (sea level):",
              worst);
  for (std::size_t level = kLevels; level >= 1; --level)
    std::printf(" %.1f", g->heightAboveEllipsoidMeters[outIndex(*g, level, 0)] -
                             full->heightAboveEllipsoidMeters[outIndex(*full, level, 0)]);
  std::printf(" m (levels 10 .. 1)\n");
  EXPECT_GT(worst, 5.0);  // the made-up atmosphere is not the standard one

  // Without any surface pressure: ps = 101325 Pa for every column, said so.
  std::vector<Message> tOnly;
  for (const Message& m : all)
    if (m.shortName == "t") tOnly.push_back(m);
  for (std::size_t s : writeGrib(dir + "/t_only.grib2", tOnly)) ASSERT_GT(s, 0u);
  auto bare = readGridVolume(dir + "/t_only.grib2");
  ASSERT_TRUE(bare.ok()) << bare.error();
  EXPECT_TRUE(bare->approximateHeights);
  EXPECT_TRUE(contains(bare->heightNote, "ps = 101325 Pa")) << bare->heightNote;
  EXPECT_TRUE(contains(bare->heightNote,
                       "a surface pressure (sp on the surface or lnsp on model level 1) valid at "
                       "2024-01-15T12:00:00Z"))
      << bare->heightNote;
  for (std::size_t level = 1; level <= kLevels; ++level) {
    const double pFull = 0.5 * (halfPressure(level - 1, 101325.0) + halfPressure(level, 101325.0));
    ASSERT_NEAR(bare->heightAboveEllipsoidMeters[outIndex(*bare, level, 5)],
                ellipsoidHeight(9.80665 * standardAtmosphereGeopotentialHeightMeters(pFull), 5), 0.01);
  }
}

TEST(GribModelLevels, StandardAtmosphereTemperaturesIntegrateToTheStandardAtmosphere) {
  // A physical check independent of the formula: a dry column at sea level (ps = 101325 Pa,
  // z = 0) whose temperatures are the standard atmosphere's at each level's pressure integrates
  // to the standard-atmosphere heights of those pressures, up to the discretisation. 60 levels
  // evenly spaced in ln p from 10 hPa down (pure pressure levels: a = p, b = 0, the bottom half
  // level b = 1): each layer is ~0.08 in ln p (~600 m). IFS's scheme is exact for an isothermal
  // layer; what is left: a full level's placement (alpha against ln(p(k+1/2) / p(k)) at the mean
  // pressure p(k)) ~1 m, not cumulative; a temperature linear in height held constant over each
  // layer, ~1.5 m accumulated through the troposphere; the layer across the tropopause kink
  // (11 km), ~1 m carried upwards; IFS's Rd = 287.06 against the standard atmosphere's 287.053,
  // 2.5e-5 of the height (0.8 m at 31 km). Sum 4.3 m: 5 m below the top level (its own bound
  // below). (With the 10 coarse levels of the other tests the same check is off by up to
  // 123 m: layers of 3-4 km across the tropopause.)
  useTestCache();
  const std::string file = atmoglobe_test::freshTestDir("grib_hybrid") + "/ussa.grib2";
  constexpr std::size_t n = 60;
  const double ps = 101325.0, step = std::log(ps / 1000.0) / static_cast<double>(n - 1);
  std::vector<double> a(n + 1, 0.0), b(n + 1, 0.0);
  for (std::size_t i = 1; i < n; ++i) a[i] = ps * std::exp(-static_cast<double>(n - i) * step);  // 1000 Pa at i = 1
  b[n] = 1.0;
  const std::vector<double> pv = pvOf(a, b);
  auto half = [&](std::size_t i) { return a[i] + b[i] * ps; };
  auto fullPressure = [&](std::size_t k) { return 0.5 * (half(k - 1) + half(k)); };
  auto stdTemperature = [](double pPa) {
    const double h = standardAtmosphereGeopotentialHeightMeters(pPa);
    if (h < 11000.0) return 288.15 - 0.0065 * h;  // USSA 1976, its first four layers
    if (h < 20000.0) return 216.65;
    if (h < 32000.0) return 216.65 + 0.001 * (h - 20000.0);
    return 228.65 + 0.0028 * (h - 32000.0);
  };
  std::vector<Message> m = {{"sp", "surface", 0, field([&](std::size_t) { return ps; }), {}},
                            {"z", "surface", 0, field([](std::size_t) { return 0.0; }), {}}};
  for (std::size_t k = 1; k <= n; ++k) {
    const double t = stdTemperature(fullPressure(k));
    m.push_back({"t", "hybrid", static_cast<long>(k), field([t](std::size_t) { return t; }), pv});
  }
  for (std::size_t s : writeGrib(file, m)) ASSERT_GT(s, 0u);
  auto g = readGridVolume(file, options("", false));
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->heightSource, HeightSource::HydrostaticIntegration);
  ASSERT_EQ(g->nz, n);
  double worst = 0;
  for (std::size_t level = 1; level <= n; ++level) {
    const double expected = geometricFromGeopotentialHeightMeters(
        standardAtmosphereGeopotentialHeightMeters(fullPressure(level)), latOfRow(0));
    const double got = g->heightMeters(n - level, kNj - 1, 0);  // file row 0
    if (level == 1) {
      // The top level spans ln 2 above half level 3/2 (p = 0 at the top) with its own
      // temperature, where the standard atmosphere warms by 2.8 K/km: off by at most
      // Rd |T(1) - T(3/2)| ln 2 / g0 (measured: 135 m at 36 km).
      const double bound =
          287.06 * std::fabs(stdTemperature(fullPressure(1)) - stdTemperature(half(1))) * std::log(2.0) / 9.80665;
      std::printf("top level (%.0f Pa): hydrostatic - standard atmosphere = %.1f m (bound %.1f m)\n", fullPressure(1),
                  got - expected, bound);
      EXPECT_NEAR(got, expected, bound);
      continue;
    }
    worst = std::max(worst, std::fabs(got - expected));
    EXPECT_NEAR(got, expected, 5.0) << "level " << level << " at " << fullPressure(level) << " Pa";
  }
  std::printf("60-level standard-atmosphere column, levels 60 .. 2: max |hydrostatic - standard atmosphere| = %.2f m\n",
              worst);
}

TEST(GribModelLevels, GeneralVerticalHeightsFromHhl) {
  ASSERT_TRUE(defaultEgm96Grid().ok());
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_hhl");
  // ICON's layout: 5 layers (generalVerticalLayer 1 .. 5, 1 = top), HHL on the 6 half levels
  // (generalVertical, height above sea level), written once at 00Z; t at 12Z; w on the half levels.
  const std::vector<double> grid = {6, 1, 1.5, 2.5, 3.5, 4.5};  // nlev, grid number, uuid bytes
  auto hhl = [](long half, std::size_t p) {                     // terrain-following, 12 km top
    const double ground = 150.0 * static_cast<double>(p);
    return ground + (12000.0 - ground) * std::pow((6.0 - static_cast<double>(half)) / 5.0, 1.5);
  };
  std::vector<Message> m;
  for (long h = 1; h <= 6; ++h) {
    m.push_back({"HHL", "generalVertical", h, field([&](std::size_t p) { return hhl(h, p); }), grid, 0, 3, 6});
    m.push_back({"w", "generalVertical", h,
                 field([h](std::size_t p) { return 0.1 * static_cast<double>(h) + 0.01 * static_cast<double>(p); }),
                 grid, 1200, 2, 9});
  }
  for (long k = 1; k <= 5; ++k)
    m.push_back({"t", "generalVerticalLayer", k,
                 field([k](std::size_t p) { return 220.0 + 10.0 * static_cast<double>(k) + static_cast<double>(p); }),
                 grid, 1200, 0, 0});
  for (std::size_t s : writeGrib(dir + "/icon.grib2", m)) ASSERT_GT(s, 0u);

  auto g = readGridVolume(dir + "/icon.grib2", options("t"));
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->variable, "t:generalVerticalLayer");
  EXPECT_EQ(g->verticalKind, VerticalKind::GeneralVertical);
  EXPECT_EQ(g->heightSource, HeightSource::HeightField);
  EXPECT_FALSE(g->approximateHeights);
  EXPECT_TRUE(contains(g->heightNote,
                       "mean of the half-level heights k and k+1 of 'HHL:generalVertical' (valid at "
                       "2024-01-15T00:00:00Z)"))
      << g->heightNote;
  ASSERT_EQ(g->nz, 5u);
  EXPECT_EQ(g->levelValues, (std::vector<double>{5, 4, 3, 2, 1}));
  const auto& geoid = defaultEgm96Grid();
  for (std::size_t p = 0; p < kPoints; ++p) {
    const double n = geoid->undulationMeters(latOfRow(p / kNi), lonOfColumn(p % kNi));
    const std::size_t j = kNj - 1 - p / kNi, i = p % kNi;
    for (long k = 1; k <= 5; ++k) {
      const double expected = 0.5 * (hhl(k, p) + hhl(k + 1, p)) + n;
      ASSERT_NEAR(g->heightMeters(static_cast<std::size_t>(5 - k), j, i), expected, 0.01) << p << " " << k;
    }
  }
  // Vertical velocity (ecCodes' wz) on the half levels: HHL's heights themselves.
  auto w = readGridVolume(dir + "/icon.grib2", options("wz"));
  ASSERT_TRUE(w.ok()) << w.error();
  ASSERT_EQ(w->nz, 6u);
  const double n0 = geoid->undulationMeters(44.0, 6.0);
  for (long h = 1; h <= 6; ++h)
    ASSERT_NEAR(w->heightMeters(static_cast<std::size_t>(6 - h), 0, 0), hhl(h, 8) + n0, 0.01) << h;

  // Without HHL in the file: refused, saying why; info lists the variable with the reason.
  std::vector<Message> noHhl;
  for (const Message& x : m)
    if (x.shortName != "HHL") noHhl.push_back(x);
  for (std::size_t s : writeGrib(dir + "/no_hhl.grib2", noHhl)) ASSERT_GT(s, 0u);
  auto r = readGridVolume(dir + "/no_hhl.grib2", options("t"));
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error(),
                       "no_hhl.grib2: variable t:generalVerticalLayer: GRIB generalVerticalLayer levels "
                       "take their heights from the half-level heights HHL (ICON, COSMO), and the file "
                       "has no HHL on generalVertical levels"))
      << r.error();

  // HHL of another vertical grid (another uuid): refused.
  std::vector<Message> other = m;
  for (Message& x : other)
    if (x.shortName == "HHL") x.pv[5] = 9.5;
  for (std::size_t s : writeGrib(dir + "/other_grid.grib2", other)) ASSERT_GT(s, 0u);
  auto o = readGridVolume(dir + "/other_grid.grib2", options("t"));
  ASSERT_FALSE(o.ok());
  EXPECT_TRUE(contains(o.error(), "variable HHL:generalVertical: message at byte")) << o.error();
  EXPECT_TRUE(contains(o.error(), "is on another vertical grid than the levels read")) << o.error();
}

TEST(GribModelLevels, BadHybridInputNamesWhatIsWrong) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_hybrid_bad");
  const std::vector<double> pv = pvOf(kA, kB);
  auto t = [](long level, const std::vector<double>& coefficients) {
    return Message{"t", "hybrid", level, field([](std::size_t) { return 250.0; }), coefficients};
  };
  // A pv array of 5 levels (12 values) under a message on model level 8.
  const std::vector<double> pv5 = pvOf({0, 5000, 20000, 15000, 5000, 0}, {0, 0, 0.1, 0.4, 0.8, 1});
  ASSERT_GT(writeGrib(dir + "/pv5.grib2", {t(8, pv5), t(3, pv5)}).front(), 0u);
  auto r = readGridVolume(dir + "/pv5.grib2");
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error(),
                       "pv5.grib2: variable t:hybrid: model level 8 is not one of the levels 1 .. 5 that "
                       "its pv array (12 values) defines"))
      << r.error();

  // lnsp with a missing point (bitmap): the surface pressure is not made up.
  std::vector<double> lnsp = field([](std::size_t p) { return std::log(surfacePressure(p)); });
  lnsp[6] = std::nan("");
  ASSERT_GT(writeGrib(dir + "/lnsp.grib2", {{"lnsp", "hybrid", 1, lnsp, pv}, t(10, pv)}).front(), 0u);
  r = readGridVolume(dir + "/lnsp.grib2", options("t"));
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error(),
                       "lnsp.grib2: variable lnsp:hybrid: log of the surface pressure missing or not "
                       "finite at row 1, column 2 (model level 1, valid at 2024-01-15T12:00:00Z)"))
      << r.error();

  // Coefficients whose half-level pressures decrease downwards.
  std::vector<double> a = kA, b = kB;
  std::swap(a[7], a[8]);
  std::swap(b[7], b[8]);
  ASSERT_GT(writeGrib(dir + "/order.grib2", {t(8, pvOf(a, b))}).front(), 0u);
  r = readGridVolume(dir + "/order.grib2");
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error(),
                       "order.grib2: variable t:hybrid: the half-level pressures a + b ps of its pv array "
                       "do not increase downwards at model level 8"))
      << r.error();

  // Two levels of one variable on different vertical grids.
  std::vector<double> pv2 = pv;
  pv2[3] += 1.0;
  ASSERT_GT(writeGrib(dir + "/two.grib2", {t(10, pv), t(9, pv2)}).front(), 0u);
  r = readGridVolume(dir + "/two.grib2");
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error(), "two.grib2: variable t:hybrid: message at byte")) << r.error();
  EXPECT_TRUE(contains(r.error(), "(level 9) is on another vertical grid than the levels read")) << r.error();

  // A hybrid message without pv.
  ASSERT_GT(writeGrib(dir + "/nopv.grib2", {t(4, {})}).front(), 0u);
  r = readGridVolume(dir + "/nopv.grib2");
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error(), "no pv array (PVPresent = 0): the coefficients of the hybrid levels are missing"))
      << r.error();
}

// The sparse IFS sample (model levels 1, 51, 101 of 137, t only): pressures from its pv at the
// standard surface pressure, standard-atmosphere heights, approximate.
TEST(GribModelLevelsReal, SparseIfsSampleReadsApproximately) {
  const std::string file = atmoglobe_test::testDataPath("grids_grib/regular_gg_ml_g2.grib");
  SKIP_WITHOUT_TEST_DATA(file);
  ASSERT_TRUE(defaultEgm96Grid().ok());
  useTestCache();
  auto g = readGridVolume(file);
  ASSERT_TRUE(g.ok()) << g.error();
  EXPECT_EQ(g->variable, "t:hybrid");
  EXPECT_EQ(g->verticalKind, VerticalKind::HybridSigmaPressure);
  EXPECT_EQ(g->heightSource, HeightSource::StandardAtmosphere);
  EXPECT_TRUE(g->approximateHeights);
  EXPECT_EQ(g->levelValues, (std::vector<double>{101, 51, 1}));
  for (const char* part :
       {"137 levels from pv", "ps = 101325 Pa",
        "a surface pressure (sp on the surface or lnsp on model level 1) valid at 2018-04-06T00:00:00Z",
        "t on every model level from 137 (the bottom) up to 1", "(it has 3 of those 137)",
        "the surface geopotential (z on model level 1 or on the surface, or orog)"})
    EXPECT_TRUE(contains(g->heightNote, part)) << part << "\n" << g->heightNote;

  // The pv array and the messages' lengths read by ecCodes here, the pressures by hand at 101325 Pa.
  std::unique_ptr<FILE, decltype(&std::fclose)> f(std::fopen(file.c_str(), "rb"), &std::fclose);
  ASSERT_TRUE(f);
  std::vector<double> pv;
  std::uint64_t messageBytes = 0;
  int err = 0;
  while (codes_handle* raw = codes_handle_new_from_file(nullptr, f.get(), PRODUCT_GRIB, &err)) {
    std::unique_ptr<codes_handle, decltype(&codes_handle_delete)> h(raw, &codes_handle_delete);
    long length = 0;
    ASSERT_EQ(codes_get_long(h.get(), "totalLength", &length), CODES_SUCCESS);
    messageBytes += static_cast<std::uint64_t>(length);
    std::size_t n = 0;
    ASSERT_EQ(codes_get_size(h.get(), "pv", &n), CODES_SUCCESS);
    ASSERT_EQ(n, 276u);
    pv.resize(n);
    ASSERT_EQ(codes_get_double_array(h.get(), "pv", pv.data(), &n), CODES_SUCCESS);
  }
  EXPECT_EQ(g->bytesRead, messageBytes);  // its three messages, once each
  const auto& geoid = defaultEgm96Grid();
  const std::size_t j = 40, i = 100;
  const double lat = g->latDeg[j], lon = g->lonDeg[i];
  const std::vector<int> levels = {101, 51, 1};
  for (std::size_t k = 0; k < 3; ++k) {
    const int l = levels[k];
    const double above = pv[l - 1] + pv[138 + l - 1] * 101325.0, below = pv[l] + pv[138 + l] * 101325.0;
    const double h0 =
        geometricFromGeopotentialHeightMeters(standardAtmosphereGeopotentialHeightMeters(0.5 * (above + below)), lat) +
        geoid->undulationMeters(lat, lon);
    EXPECT_NEAR(g->heightMeters(k, j, i), h0, 0.01 + 1e-6 * h0) << l;  // float storage: 4 mm at 80 km
  }
  // Model level 1 of IFS L137: 1 Pa, about 80 km up; level 101 about 4 km.
  EXPECT_NEAR(g->heightMeters(2, j, i), 80000.0, 2000.0);
  EXPECT_NEAR(g->heightMeters(0, j, i), 4000.0, 500.0);

  // The hybrid t beside a pressure-level t in one file reads too.
  auto mixed =
      readGridVolume(atmoglobe_test::testDataPath("grids_grib/t_on_different_level_types.grib"), options("t:hybrid"));
  ASSERT_TRUE(mixed.ok()) << mixed.error();
  EXPECT_EQ(mixed->levelValues, (std::vector<double>{100}));
  EXPECT_TRUE(mixed->approximateHeights);
}
