// Format detection from content, dispatch, default field choice, and the `info` descriptions.
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/RadarReader.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

using namespace atmoglobe::volume;

namespace {
const std::string kData = atmoglobe_test::testDataDir();
const std::string kKaSacr = kData + "/radar_cfradial/example_plot_ppi_single_sweep.nc";
const std::string kMll = kData + "/radar_cfradial/MLL2217907250U.003.nc";
const std::string kDow8 = kData + "/radar_cfradial/cfrad.20211011_201733.023_to_20211011_201745.299_DOW8_RHI.nc";
const std::string kAu40 = kData + "/radar_odim/40_20181220_060630.pvol.h5";
const std::string kBewid = kData + "/radar_odim/bewid.pvol.hdf";
const std::string kNexrad = kData + "/radar_nexrad/KLBB20160601_150025_V06";

std::string tempDir() {
  const auto d = std::filesystem::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "radar_reader";
  std::filesystem::create_directories(d);
  return d.string();
}
}  // namespace

TEST(RadarReaderDetect, RealFilesByContent) {
  SKIP_WITHOUT_TEST_DATA(kKaSacr, kMll, kDow8, kAu40, kBewid, kNexrad);
  for (const auto& [path, want] : {std::pair{kKaSacr, RadarFormat::CfRadial},
                                   {kMll, RadarFormat::CfRadial},
                                   {kDow8, RadarFormat::CfRadial},
                                   {kAu40, RadarFormat::OdimH5},
                                   {kBewid, RadarFormat::OdimH5},
                                   {kNexrad, RadarFormat::NexradLevel2}}) {
    auto f = detectRadarFormat(path);
    ASSERT_TRUE(f.ok()) << f.error();
    EXPECT_EQ(*f, want) << path;
  }
}

TEST(RadarReaderDetect, NameIsIgnored) {
  SKIP_WITHOUT_TEST_DATA(kBewid, kMll);
  // An ODIM file renamed .nc is still ODIM; a CfRadial file renamed .h5 is still CfRadial.
  const std::string odimAsNc = tempDir() + "/odim_named.nc";
  const std::string cfAsH5 = tempDir() + "/cfradial_named.h5";
  std::filesystem::copy_file(kBewid, odimAsNc, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(kMll, cfAsH5, std::filesystem::copy_options::overwrite_existing);
  EXPECT_EQ(detectRadarFormat(odimAsNc).value(), RadarFormat::OdimH5);
  EXPECT_EQ(detectRadarFormat(cfAsH5).value(), RadarFormat::CfRadial);
  ReadOptions o;
  o.loadValues = false;
  auto v = readRadarVolume(odimAsNc, o);
  ASSERT_TRUE(v.ok()) << v.error();
  EXPECT_EQ(v->format, "ODIM_H5");
  EXPECT_EQ(v->sweeps.size(), 11u);
}

TEST(RadarReaderDetect, MissingFileIsAnError) {
  const std::string p = tempDir() + "/does_not_exist.h5";
  auto f = detectRadarFormat(p);
  ASSERT_FALSE(f.ok());
  EXPECT_NE(f.error().find(p), std::string::npos);
}

TEST(RadarReaderDispatch, ReadsEachCfRadialAndOdimFile) {
  SKIP_WITHOUT_TEST_DATA(kKaSacr, kMll, kDow8, kAu40, kBewid);
  for (const std::string& p : {kKaSacr, kMll, kDow8, kAu40, kBewid}) {
    auto v = readRadarVolume(p, ReadOptions{});
    ASSERT_TRUE(v.ok()) << v.error();
    EXPECT_EQ(v->sourcePath, p);
    EXPECT_FALSE(v->loadedField.name.empty()) << p;
    for (std::size_t i = 1; i < v->sweeps.size(); ++i)
      EXPECT_LE(v->sweeps[i - 1].fixedAngleDeg, v->sweeps[i].fixedAngleDeg) << p;  // sorted by angle
  }
}

TEST(RadarReaderDefaultField, PrefersReflectivityByMeaning) {
  auto f = [](const char* name, const char* units = "", const char* standardName = "") {
    return FieldInfo{name, units, standardName};
  };
  EXPECT_EQ(chooseDefaultField({f("VRADH"), f("DBZH")}), "DBZH");
  EXPECT_EQ(chooseDefaultField({f("velocity"), f("reflectivity_at_cor")}), "reflectivity_at_cor");
  EXPECT_EQ(chooseDefaultField({f("VEL"), f("DBZHC")}), "DBZHC");
  EXPECT_EQ(chooseDefaultField({f("VEL"), f("WIDTH")}), "VEL");
  EXPECT_EQ(chooseDefaultField({}), "");
  // Reflectivity spelled "dBZ" after a velocity field: still chosen.
  EXPECT_EQ(chooseDefaultField({f("VRAD", "m/s"), f("dBZ", "dBZ")}), "dBZ");
  EXPECT_EQ(chooseDefaultField({f("VRAD"), f("dBZ")}), "dBZ") << "by name, in any case";
  // standard_name wins over names and units; among several, the uncorrected DBZH before TH.
  const DefaultField bySn =
      chooseDefaultFieldWithReason({f("DBZH", "dBZ"), f("ZZ", "1", "equivalent_reflectivity_factor"), f("VEL", "m/s")});
  EXPECT_EQ(bySn.name, "ZZ");
  EXPECT_NE(bySn.reason.find("standard_name"), std::string::npos) << bySn.reason;
  EXPECT_EQ(chooseDefaultField({f("TH", "dBZ"), f("DBZH", "dBZ")}), "DBZH");
  // Units alone: a field named oddly but in dBZ.
  const DefaultField byUnits = chooseDefaultFieldWithReason({f("V", "m/s"), f("Zfoo", "DBZ")});
  EXPECT_EQ(byUnits.name, "Zfoo");
  EXPECT_NE(byUnits.reason.find("units"), std::string::npos) << byUnits.reason;
  // No reflectivity: the first field, and it says so.
  const DefaultField none = chooseDefaultFieldWithReason({f("VRADH", "m/s"), f("WRADH", "m/s")});
  EXPECT_EQ(none.name, "VRADH");
  EXPECT_NE(none.reason.find("no reflectivity"), std::string::npos);
}

TEST(FieldKind, KindsByStandardNameNameAndUnits) {
  EXPECT_EQ(classifyField({"x", "", "radial_velocity_of_scatterers_away_from_instrument"}).kind, FieldKind::Velocity);
  EXPECT_EQ(classifyField({"VRADH", "", ""}).kind, FieldKind::Velocity);
  EXPECT_EQ(classifyField({"vel", "", ""}).kind, FieldKind::Velocity);
  EXPECT_EQ(classifyField({"spectrum_width", "m/s", ""}).kind, FieldKind::SpectrumWidth);
  EXPECT_EQ(classifyField({"my_width", "m/s", ""}).kind, FieldKind::SpectrumWidth);
  EXPECT_EQ(classifyField({"doppler", "m/s", ""}).kind, FieldKind::Velocity);
  EXPECT_EQ(classifyField({"ZDR", "dB", ""}).kind, FieldKind::DifferentialReflectivity);
  EXPECT_EQ(classifyField({"RHO", "", ""}).kind, FieldKind::CorrelationCoefficient);
  EXPECT_EQ(classifyField({"PHI", "deg", ""}).kind, FieldKind::DifferentialPhase);
  EXPECT_EQ(classifyField({"k", "deg/km", ""}).kind, FieldKind::SpecificDifferentialPhase);
  EXPECT_EQ(classifyField({"SNR", "dB", ""}).kind, FieldKind::Other);
}

TEST(FieldKind, DefaultColoursFollowTheKind) {
  const ValueRange range{-30.0, 30.0};
  // Reflectivity: the NWS table.
  EXPECT_EQ(defaultTransferFor(FieldKind::Reflectivity, NAN, range).colors.name(), nwsReflectivityTable().name());
  // Velocity: diverging, centred on zero, over +-Nyquist: green towards, red away, grey and
  // fainter at zero, symmetric in opacity.
  const TransferFunction v = defaultTransferFor(FieldKind::Velocity, 26.5, range);
  EXPECT_DOUBLE_EQ(v.colors.stops().front().value, -26.5);
  EXPECT_DOUBLE_EQ(v.colors.stops().back().value, 26.5);
  const glm::dvec4 towards = v.classify(-20.0), away = v.classify(20.0), still = v.classify(0.0);
  EXPECT_GT(towards.g, towards.r);
  EXPECT_GT(away.r, away.g);
  EXPECT_NEAR(still.r, still.g, 0.01);
  EXPECT_LT(still.a, 0.5 * towards.a);
  EXPECT_NEAR(v.classify(-13.0).a, v.classify(13.0).a, 0.02);
  // Without a Nyquist velocity: the largest |value| (velocities are coded within +-Nyquist),
  // else 30 m/s.
  EXPECT_DOUBLE_EQ(defaultTransferFor(FieldKind::Velocity, NAN, {-7.4, 7.2}).colors.stops().back().value, 7.4);
  EXPECT_DOUBLE_EQ(defaultTransferFor(FieldKind::Velocity, NAN, {NAN, NAN}).colors.stops().back().value, 30.0);
  // A user's table wins; "auto" follows the kind; a bad .pal is an error naming the file.
  auto nws = transferForField("NWS", FieldInfo{"VRADH", "m/s", {}}, 26.5, range);
  ASSERT_TRUE(nws);
  EXPECT_EQ(nws->colors.name(), nwsReflectivityTable().name());
  auto autoVel = transferForField("auto", FieldInfo{"VRADH", "m/s", {}}, 26.5, range);
  ASSERT_TRUE(autoVel);
  EXPECT_EQ(autoVel->colors.name(), "Velocity");
  auto bad = transferForField("/nonexistent/x.pal", FieldInfo{"DBZH", "dBZ", {}}, NAN, range);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("/nonexistent/x.pal"), std::string::npos);
}

// Model variables by what they measure (FieldKind.h, docs/grids.md's table): zero-based amounts
// are transparent where the model has none (and up to 2 % of the largest value), smooth fields
// only in their upper half and faintly; the colour table chosen by "auto" keeps that opacity.
TEST(FieldKind, VariablesAreDrawnByWhatTheyMeasure) {
  // Names as the grid reader gives them: netCDF-4 paths ("/QRAIN", "/forecast/clwc").
  for (const FieldInfo& f : {FieldInfo{"/QRAIN", "kg kg-1", {}}, FieldInfo{"/forecast/clwc", "kg kg**-1", {}},
                             FieldInfo{"x", "kg kg-1", "mass_fraction_of_cloud_liquid_water_in_air"},
                             FieldInfo{"tp", "m", {}}, FieldInfo{"precip", "mm", {}}, FieldInfo{"CLDFRA", "", {}},
                             FieldInfo{"c", "1", "cloud_area_fraction_in_atmosphere_layer"}})
    EXPECT_EQ(variableAmountOf(f), VariableAmount::ZeroBased) << f.name << " " << f.standardName;
  for (const FieldInfo& f : {FieldInfo{"t", "K", {}}, FieldInfo{"z", "m**2 s**-2", {}}, FieldInfo{"U", "m s-1", {}},
                             FieldInfo{"q", "kg kg**-1", "specific_humidity"}, FieldInfo{"QVAPOR", "kg kg-1", {}},
                             FieldInfo{"T", "K", "air_temperature"}})
    EXPECT_EQ(variableAmountOf(f), VariableAmount::Smooth) << f.name << " " << f.standardName;

  for (const char* colors : {"auto", "viridis"}) {
    auto rain = transferForField(colors, FieldInfo{"/QRAIN", "kg kg-1", {}}, NAN, {0.0, 0.004});
    ASSERT_TRUE(rain) << rain.error();
    EXPECT_DOUBLE_EQ(rain->colors.stops().front().value, 0.0);
    EXPECT_DOUBLE_EQ(rain->colors.stops().back().value, 0.004);
    EXPECT_EQ(rain->classify(0.0).a, 0.0);
    EXPECT_EQ(rain->classify(0.00008).a, 0.0);  // 2 % of the largest value
    EXPECT_GT(rain->classify(0.0005).a, 0.0);
    EXPECT_NEAR(rain->classify(0.001).a, 0.9, 1e-9);  // a quarter of the largest value
    auto temperature = transferForField(colors, FieldInfo{"t", "K", {}}, NAN, {180.0, 310.0});
    ASSERT_TRUE(temperature) << temperature.error();
    EXPECT_EQ(temperature->classify(245.0).a, 0.0);  // the middle of the range
    EXPECT_NEAR(temperature->classify(310.0).a, 0.05, 1e-9);
    EXPECT_NEAR(temperature->classify(277.5).a, 0.025, 1e-9);
  }
  // The user's ramp still wins (withOpacityRamp is applied after, engine/VolumeSourceGL.cpp).
}

TEST(RadarReaderTime, NormalizeIso8601) {
  EXPECT_EQ(normalizeIso8601("2021-10-11 20:17:33.023"), "2021-10-11T20:17:33Z");
  EXPECT_EQ(normalizeIso8601("2020-03-12T00:30:09Z"), "2020-03-12T00:30:09Z");
  EXPECT_EQ(normalizeIso8601("2020-03-12"), "");
  EXPECT_EQ(normalizeIso8601("garbage that is long enough"), "");
}

TEST(RadarReaderDescribe, JsonHasTheInfoFields) {
  SKIP_WITHOUT_TEST_DATA(kBewid);
  ReadOptions o;
  o.loadValues = false;
  auto v = readRadarVolume(kBewid, o);
  ASSERT_TRUE(v.ok()) << v.error();
  const auto j = nlohmann::json::parse(describeVolumeJson(*v));
  EXPECT_EQ(j.at("format"), "ODIM_H5");
  EXPECT_DOUBLE_EQ(j.at("site").at("lat_deg").get<double>(), 49.9143);
  EXPECT_DOUBLE_EQ(j.at("site").at("lon_deg").get<double>(), 5.5056);
  EXPECT_DOUBLE_EQ(j.at("site").at("height_m").get<double>(), 590.0);
  EXPECT_EQ(j.at("site").at("height_datum"), "msl");
  EXPECT_EQ(j.at("time"), "2019-06-06T00:00:16Z");
  ASSERT_EQ(j.at("sweeps").size(), 11u);
  EXPECT_DOUBLE_EQ(j.at("sweeps")[6].at("fixed_angle_deg").get<double>(), 4.8);
  EXPECT_EQ(j.at("sweeps")[6].at("gates").get<int>(), 500);
  EXPECT_EQ(j.at("sweeps")[6].at("rays").get<int>(), 360);
  EXPECT_DOUBLE_EQ(j.at("sweeps")[6].at("first_gate_m").get<double>(), 125.0);
  EXPECT_DOUBLE_EQ(j.at("sweeps")[6].at("gate_spacing_m").get<double>(), 250.0);
  EXPECT_EQ(j.at("sweeps")[6].at("mode"), "PPI");
  ASSERT_EQ(j.at("fields").size(), 1u);
  EXPECT_EQ(j.at("fields")[0].at("name"), "DBZH");
  EXPECT_EQ(j.at("fields")[0].at("units"), "dBZ");
}

TEST(RadarReaderDescribe, TextNamesRhiAndUnits) {
  SKIP_WITHOUT_TEST_DATA(kDow8);
  ReadOptions o;
  o.loadValues = false;
  auto v = readRadarVolume(kDow8, o);
  ASSERT_TRUE(v.ok()) << v.error();
  const std::string t = describeVolumeText(*v);
  EXPECT_NE(t.find("CfRadial"), std::string::npos) << t;
  EXPECT_NE(t.find("RHI"), std::string::npos) << t;
  EXPECT_NE(t.find("DBZHC [dBZ]"), std::string::npos) << t;
  EXPECT_NE(t.find("2021-10-11T20:17:33Z"), std::string::npos) << t;
  const auto j = nlohmann::json::parse(describeVolumeJson(*v));
  EXPECT_EQ(j.at("sweeps")[0].at("mode"), "RHI");
  EXPECT_EQ(j.at("sweeps")[0].at("fixed_angle_kind"), "azimuth");
}
