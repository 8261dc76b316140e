// Corrupted files: bit flips and headers claiming terabytes. Every read either
// succeeds or fails with a message naming the file; none may crash, hang or allocate what the file
// cannot back (the sanitized CI build runs these under AddressSanitizer, which also fails an
// allocation of terabytes). Inputs: the small synthetic grid seed of the fuzz corpus
// (fuzz/corpus/grid, made with ncgen) and, for the radar readers, the real sample files.
#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/NexradReader.h>
#include <atmoglobe/volume/RainbowReader.h>
#include <atmoglobe/volume/SigmetReader.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <random>
#include <string>
#include <vector>

using namespace atmoglobe::volume;
using namespace atmoglobe::io;  // NetcdfFile

namespace {

std::vector<unsigned char> readAll(const std::string& path, std::size_t maxBytes = static_cast<std::size_t>(-1)) {
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() > maxBytes) bytes.resize(maxBytes);
  return bytes;
}

void writeAll(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// `bytes` with 1 to 4 single-bit flips at positions in [from, size) drawn from `rng`.
std::vector<unsigned char> flipBits(std::vector<unsigned char> bytes, std::mt19937& rng, std::size_t from = 0) {
  std::uniform_int_distribution<std::size_t> at(from, bytes.size() - 1);
  std::uniform_int_distribution<int> bit(0, 7), count(1, 4);
  for (int n = count(rng); n > 0; --n) bytes[at(rng)] ^= static_cast<unsigned char>(1u << bit(rng));
  return bytes;
}

const std::string kGridSeed = std::string(ATMOGLOBE_SOURCE_DIR) + "/fuzz/corpus/grid/small-classic.nc";

/// Sets the 32-bit big-endian length of classic-format dimension `name` (3 characters) to `length`.
bool setClassicDimLength(std::vector<unsigned char>& bytes, const std::string& name, std::uint32_t length) {
  const std::string key = std::string("\0\0\0\3", 4) + name + std::string(1, '\0');
  const std::string text(bytes.begin(), bytes.end());
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return false;
  for (int i = 0; i < 4; ++i) bytes[at + key.size() + i] = static_cast<unsigned char>(length >> (24 - 8 * i));
  return true;
}

}  // namespace

TEST(CorruptInput, BitFlippedGridsReadOrFailNamingTheFile) {
  const std::string dir = atmoglobe_test::freshTestDir("corrupt_input");
  const std::vector<unsigned char> whole = readAll(kGridSeed);
  ASSERT_GT(whole.size(), 1000u) << kGridSeed;
  ASSERT_TRUE(readGridVolume(kGridSeed).ok()) << "the intact seed must read";
  // Flips in the data section only (coordinates, levels, times, values): flips in the classic
  // header can crash netCDF-C 4.9.0 itself inside nc_open (ncdump segfaults on such files too;
  // docs/robustness.md, fuzz_grid), which no caller can prevent. The header ends with the last
  // variable's attributes ("air_temperature", padded to 16 bytes) and its type, size and offset.
  const std::string text(whole.begin(), whole.end());
  const std::size_t lastText = text.rfind("air_temperature");
  ASSERT_NE(lastText, std::string::npos);
  const std::size_t dataStart = lastText + 16 + 12;
  std::mt19937 rng(14);
  int failures = 0;
  constexpr int kVariants = 200;
  for (int i = 0; i < kVariants; ++i) {
    const std::string path = dir + "/flip" + std::to_string(i) + ".nc";
    writeAll(path, flipBits(whole, rng, dataStart));
    auto r = readGridVolume(path);
    auto d = describeGridFile(path);
    if (!r.ok()) {
      ++failures;
      EXPECT_EQ(r.error().rfind(path, 0), 0u) << r.error();
    }
    if (!d.ok()) {
      EXPECT_EQ(d.error().rfind(path, 0), 0u) << d.error();
    }
  }
  // Flips in the coordinate variables (lat, lon, level: 48 of the ~780 data bytes) give NaN,
  // unsorted or out-of-range coordinates, which must be refused; a reader accepting every variant
  // would not be checking its coordinates.
  EXPECT_GT(failures, 0) << "no variant of " << kVariants << " refused";
}

TEST(CorruptInput, GridDimensionsClaimingTerabytes) {
  const std::string dir = atmoglobe_test::freshTestDir("corrupt_input_huge");
  std::vector<unsigned char> bytes = readAll(kGridSeed);
  // lat and lon of 2^31 - 1 each: dbz (time, level, lat, lon) of shorts then claims
  // 2 x 3 x (2^31)^2 x 2 bytes, about 5.5e19 bytes, in a 1.6 kB file.
  ASSERT_TRUE(setClassicDimLength(bytes, "lat", 0x7fffffffu));
  ASSERT_TRUE(setClassicDimLength(bytes, "lon", 0x7fffffffu));
  const std::string path = dir + "/terabytes.nc";
  writeAll(path, bytes);
  auto r = readGridVolume(path);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().rfind(path, 0), 0u) << r.error();
  auto d = describeGridFile(path);
  ASSERT_FALSE(d.ok());
  EXPECT_EQ(d.error().rfind(path, 0), 0u) << d.error();
  // One dimension alone (lat of 2^31 - 1: dbz claims 2.6e10 values, 51 GB).
  bytes = readAll(kGridSeed);
  ASSERT_TRUE(setClassicDimLength(bytes, "lat", 0x7fffffffu));
  const std::string one = dir + "/fifty-gigabytes.nc";
  writeAll(one, bytes);
  auto r1 = readGridVolume(one);
  ASSERT_FALSE(r1.ok());
  EXPECT_EQ(r1.error().rfind(one, 0), 0u) << r1.error();
}

TEST(CorruptInput, BitFlippedRadarFilesReadOrFailNamingTheFile) {
  const std::string sigmet = atmoglobe_test::testDataPath("radar_sigmet/SUR210819000227.RAWKPJV");
  const std::string rainbow = atmoglobe_test::testDataPath("radar_rainbow/2013051000000600dBZ.vol");
  const std::string nexrad = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");
  SKIP_WITHOUT_TEST_DATA(sigmet, rainbow, nexrad);
  ReadOptions options;
  std::mt19937 rng(14);
  // Whole Rainbow file (136 kB); the first 40 records of the Sigmet file and the first 300 kB of
  // the NEXRAD file (the volume header and its first records): each reader must also cope with
  // the cut. 40 variants each keep the test at a few seconds under AddressSanitizer.
  const std::vector<unsigned char> rainbowBytes = readAll(rainbow);
  const std::vector<unsigned char> sigmetBytes = readAll(sigmet, 40 * kSigmetRecordBytes);
  const std::vector<unsigned char> nexradBytes = readAll(nexrad, 300000);
  for (int i = 0; i < 40; ++i) {
    const std::string label = "flip" + std::to_string(i);
    auto a = readRainbow5(label + ".vol", flipBits(rainbowBytes, rng), options);
    if (!a.ok()) {
      EXPECT_NE(a.error().find(label + ".vol"), std::string::npos) << a.error();
    }
    auto b = readSigmetIris(label + ".raw", flipBits(sigmetBytes, rng), options);
    if (!b.ok()) {
      EXPECT_NE(b.error().find(label + ".raw"), std::string::npos) << b.error();
    }
    auto c = readNexradLevel2(label + ".ar2v", flipBits(nexradBytes, rng), options);
    if (!c.ok()) {
      EXPECT_NE(c.error().find(label + ".ar2v"), std::string::npos) << c.error();
    }
  }
}

TEST(CorruptInput, FuzzFoundOverlongClassicNamesAreRefused) {
  // fuzz_grid findings (fuzz/corpus/grid/crash-*): classic headers naming a dimension with
  // thousands of characters, which netCDF-C copied into NC_MAX_NAME-sized buffers (a stack
  // overflow under ASan). Now refused before netCDF-C opens the file, from disk and from memory.
  for (const char* name : {"crash-overlong-dimension-name-1.nc", "crash-overlong-dimension-name-2.nc"}) {
    const std::string path = std::string(ATMOGLOBE_SOURCE_DIR) + "/fuzz/corpus/grid/" + name;
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    auto r = readGridVolume(path);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().rfind(path, 0), 0u) << r.error();
    EXPECT_NE(r.error().find("dimension name of"), std::string::npos) << r.error();
    auto d = describeGridFile(path);
    ASSERT_FALSE(d.ok());
    EXPECT_NE(d.error().find("header is corrupt"), std::string::npos) << d.error();
    auto bytes = std::make_shared<std::vector<unsigned char>>(readAll(path));
    auto m = NetcdfFile::openMemory("in-memory.nc", bytes);
    ASSERT_FALSE(m.ok());
    EXPECT_EQ(m.error().rfind("in-memory.nc: ", 0), 0u) << m.error();
  }
}

TEST(CorruptInput, FuzzFoundUnknownClassicTypesAreRefused) {
  // fuzz_grid findings: classic headers with type 12 (NC_STRING, no classic type), for an
  // attribute of a 424-byte file cut in its header (netCDF-C 4.9.0: SEGV in NC_hashmapfree while
  // freeing what it had read) and for a variable (netCDF-C 4.9.0: SIGFPE in NC_check_vlen, a
  // division by the type's size, 0). Now refused from the header walk, naming the file.
  const std::pair<const char*, const char*> cases[] = {
      {"crash-attribute-type-12-d651a9.nc", "an attribute of unknown type 12"},
      {"crash-variable-type-12-56ba2d.nc", "a variable of unknown type 12"}};
  for (const auto& [name, message] : cases) {
    const std::string path = std::string(ATMOGLOBE_SOURCE_DIR) + "/fuzz/corpus/grid/" + name;
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    auto r = readGridVolume(path);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().rfind(path, 0), 0u) << r.error();
    EXPECT_NE(r.error().find(message), std::string::npos) << r.error();
    auto m = NetcdfFile::openMemory("in-memory.nc", std::make_shared<std::vector<unsigned char>>(readAll(path)));
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().find(std::string("in-memory.nc: not a valid netCDF file: ") + message), std::string::npos)
        << m.error();
  }
}

TEST(CorruptInput, FuzzFoundHeaderCountsBeyondTheFileAreRefused) {
  // fuzz_grid findings (fuzz/corpus/grid/oom-header-counts-*): classic headers claiming more
  // attribute values or variable dimensions than the file holds, for which netCDF-C allocated
  // 7 to 9 GB before reading them. Now refused from the header walk, naming the file.
  int files = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(ATMOGLOBE_SOURCE_DIR) + "/fuzz/corpus/grid")) {
    if (entry.path().filename().string().rfind("oom-header-counts-", 0) != 0) continue;
    ++files;
    const std::string path = entry.path().string();
    auto r = readGridVolume(path);
    ASSERT_FALSE(r.ok()) << path;
    EXPECT_EQ(r.error().rfind(path, 0), 0u) << r.error();
    EXPECT_NE(r.error().find("claimed in a file of"), std::string::npos) << r.error();
  }
  EXPECT_EQ(files, 3);
}
