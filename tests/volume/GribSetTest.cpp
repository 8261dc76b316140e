// A directory, a pattern or a list of GRIB files read as one GRIB file (centres publish one file
// per step or per parameter): files made here with ecCodes' encoder, no sample data needed. The
// set reads exactly as the same messages concatenated into one file.
#include "GribTestUtil.h"

#include <atmoglobe/volume/GridReader.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

using namespace atmoglobe::volume;
using namespace atmoglobe_test::grib;

namespace {

constexpr long kNi = 6, kNj = 4;

/// One message of t on a height above sea level at analysis time `hhmm`: values from the level,
/// the time and the point.
std::string message(long levelM, long hhmm) {
  std::vector<double> values(static_cast<std::size_t>(kNi * kNj));
  for (std::size_t p = 0; p < values.size(); ++p)
    values[p] = 250.0 + static_cast<double>(p) + 0.01 * static_cast<double>(levelM) + static_cast<double>(hhmm) / 100.0;
  return makeGribMessage("GRIB2",
                         {{"Ni", kNi},
                          {"Nj", kNj},
                          {"latitudeOfFirstGridPointInDegrees", 50.0},
                          {"longitudeOfFirstGridPointInDegrees", 5.0},
                          {"latitudeOfLastGridPointInDegrees", 47.0},
                          {"longitudeOfLastGridPointInDegrees", 10.0},
                          {"iDirectionIncrementInDegrees", 1.0},
                          {"jDirectionIncrementInDegrees", 1.0},
                          {"dataDate", 20260101L},
                          {"dataTime", hhmm},
                          {"typeOfFirstFixedSurface", 102L},
                          {"scaleFactorOfFirstFixedSurface", 0L},
                          {"scaledValueOfFirstFixedSurface", levelM}},
                         values);
}

void expectSameVolume(const GridVolume& a, const GridVolume& b) {
  EXPECT_EQ(a.variable, b.variable);
  EXPECT_EQ(a.times, b.times);
  EXPECT_EQ(a.validTime, b.validTime);
  ASSERT_EQ(a.nx, b.nx);
  ASSERT_EQ(a.ny, b.ny);
  ASSERT_EQ(a.nz, b.nz);
  EXPECT_EQ(a.values, b.values);
  EXPECT_EQ(a.heightAboveEllipsoidMeters, b.heightAboveEllipsoidMeters);
  EXPECT_EQ(a.bytesRead, b.bytesRead);
}

}  // namespace

TEST(GribSet, DirectoryPatternAndListReadAsTheSameMessagesInOneFile) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_set");
  const std::string steps = dir + "/steps";
  std::filesystem::create_directories(steps);
  std::string all;
  for (long hhmm : {0L, 1200L}) {
    std::string file;
    for (long level : {500L, 1500L, 3000L}) file += message(level, hhmm);
    ASSERT_FALSE(file.empty());
    writeFile(steps + "/t_" + std::to_string(hhmm) + ".grib2", file);
    all += file;
  }
  const std::string single = dir + "/all.grib2";
  writeFile(single, all);

  GridReadOptions o;
  o.timeIndex = 1;
  auto one = readGridVolume(single, o);
  ASSERT_TRUE(one.ok()) << one.error();
  ASSERT_EQ(one->times.size(), 2u);
  ASSERT_EQ(one->nz, 3u);
  const std::string list = steps + "/t_0.grib2," + steps + "/t_1200.grib2";
  for (const std::string& spec : {steps, steps + "/t_*.grib2", list}) {
    SCOPED_TRACE(spec);
    EXPECT_TRUE(isGridFile(spec));
    auto set = readGridVolume(spec, o);
    ASSERT_TRUE(set.ok()) << set.error();
    expectSameVolume(*one, *set);
    EXPECT_EQ(set->path, spec);
    EXPECT_NE(set->format.find("2 files"), std::string::npos) << set->format;
    // Only the second time's file was read: its three messages.
    ASSERT_EQ(set->gribMessagesRead.size(), 3u);
    for (const auto& m : set->gribMessagesRead) EXPECT_EQ(m.path, steps + "/t_1200.grib2");
    auto info = describeGridFile(spec);
    ASSERT_TRUE(info.ok()) << info.error();
    EXPECT_EQ(info->times.size(), 2u);
    EXPECT_EQ(info->messageCount, 6u);
    EXPECT_NE(describeGridText(*info).find("2 files"), std::string::npos);
  }
}

TEST(GribSet, ASetWithAFileThatIsNotGribNamesIt) {
  useTestCache();
  const std::string dir = atmoglobe_test::freshTestDir("grib_set");
  writeFile(dir + "/a.grib2", message(500, 0) + message(1500, 0));
  writeFile(dir + "/notes.txt", "not a GRIB file\n");
  auto r = readGridVolume(dir, GridReadOptions{});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find(dir + "/notes.txt is not a GRIB file"), std::string::npos) << r.error();
  auto missing = readGridVolume(dir + "/nothing_*.grib2", GridReadOptions{});
  EXPECT_FALSE(missing.ok());
}
