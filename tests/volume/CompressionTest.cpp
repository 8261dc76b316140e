// gzip/bzip2-wrapped radar files and grids: each file is compressed here, in
// memory, with zlib and libbz2 directly (not through the library), written beside the test output,
// read through readRadarVolume / the grid reader, and compared field by field with the plain read
// (site, time, sweeps, every ray angle and every gate value, NaN and -inf included). Then bad
// compressed input: a truncated stream, corrupt data, a wrapper around something that is no radar
// format, trailing garbage, and a "zip bomb" that would decompress past the limit.
#include <atmoglobe/io/Compression.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/SyntheticGrid.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <bzlib.h>
#include <gtest/gtest.h>
#include <zlib.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace atmoglobe::volume {
namespace {

using namespace io;  // Compression.h

using Bytes = std::vector<unsigned char>;

std::string outDir() {
  const auto d = std::filesystem::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "compression";
  std::filesystem::create_directories(d);
  return d.string();
}

Bytes readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string writeFile(const std::string& name, const Bytes& bytes) {
  const std::string path = outDir() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return path;
}

/// gzip (RFC 1952) with zlib's deflate: windowBits 15 + 16 writes the gzip header and trailer.
Bytes gzip(const Bytes& in, int level = 6) {
  z_stream zs{};
  EXPECT_EQ(deflateInit2(&zs, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);
  Bytes out(deflateBound(&zs, static_cast<uLong>(in.size())) + 64);
  zs.next_in = const_cast<Bytef*>(in.data());
  zs.avail_in = static_cast<uInt>(in.size());
  zs.next_out = out.data();
  zs.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&zs, Z_FINISH), Z_STREAM_END);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

Bytes bzip2(const Bytes& in) {
  unsigned int n = static_cast<unsigned int>(in.size() + in.size() / 100 + 600);
  Bytes out(n);
  EXPECT_EQ(BZ2_bzBuffToBuffCompress(reinterpret_cast<char*>(out.data()), &n,
                                     const_cast<char*>(reinterpret_cast<const char*>(in.data())),
                                     static_cast<unsigned int>(in.size()), 9, 0, 0),
            BZ_OK);
  out.resize(n);
  return out;
}

bool sameFloat(float a, float b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

/// Everything the readers fill, compared exactly (the same bytes must decode to the same floats).
void expectSameVolume(const RadarVolume& plain, const RadarVolume& wrapped, std::size_t* valuesCompared) {
  EXPECT_EQ(plain.format, wrapped.format);
  EXPECT_EQ(plain.site.name, wrapped.site.name);
  EXPECT_EQ(plain.site.latDeg, wrapped.site.latDeg);
  EXPECT_EQ(plain.site.lonDeg, wrapped.site.lonDeg);
  EXPECT_EQ(plain.site.antennaHeightMeters, wrapped.site.antennaHeightMeters);
  EXPECT_EQ(plain.timeIso8601, wrapped.timeIso8601);
  EXPECT_EQ(plain.beamWidthDeg, wrapped.beamWidthDeg);
  EXPECT_TRUE(sameFloat(static_cast<float>(plain.nyquistVelocityMps), static_cast<float>(wrapped.nyquistVelocityMps)));
  ASSERT_EQ(plain.fields.size(), wrapped.fields.size());
  for (std::size_t i = 0; i < plain.fields.size(); ++i) {
    EXPECT_EQ(plain.fields[i].name, wrapped.fields[i].name);
    EXPECT_EQ(plain.fields[i].units, wrapped.fields[i].units);
  }
  EXPECT_EQ(plain.loadedField.name, wrapped.loadedField.name);
  ASSERT_EQ(plain.sweeps.size(), wrapped.sweeps.size());
  for (std::size_t s = 0; s < plain.sweeps.size(); ++s) {
    const Sweep& a = plain.sweeps[s];
    const Sweep& b = wrapped.sweeps[s];
    EXPECT_EQ(a.fixedAngleDeg, b.fixedAngleDeg);
    EXPECT_EQ(a.mode, b.mode);
    EXPECT_EQ(a.azimuthDeg, b.azimuthDeg);
    EXPECT_EQ(a.elevationDeg, b.elevationDeg);
    EXPECT_EQ(a.firstGateRangeMeters, b.firstGateRangeMeters);
    EXPECT_EQ(a.gateSpacingMeters, b.gateSpacingMeters);
    EXPECT_EQ(a.gateCount, b.gateCount);
    ASSERT_EQ(a.values.size(), b.values.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.values.size(); ++i) differ += sameFloat(a.values[i], b.values[i]) ? 0 : 1;
    EXPECT_EQ(differ, 0u) << "sweep " << s;
    *valuesCompared += a.values.size();
  }
}

/// Reads `path` plain, then gzip- and bzip2-wrapped copies, and compares them.
void checkWrappedReadsTheSame(const std::string& path, const std::string& stem) {
  const Bytes plainBytes = readAll(path);
  ASSERT_FALSE(plainBytes.empty()) << path;
  auto plain = readRadarVolume(path, {});
  ASSERT_TRUE(plain.ok()) << plain.error();
  EXPECT_TRUE(plain->compression.empty());
  for (const auto& [kind, bytes] : {std::pair<std::string, Bytes>{"gzip", gzip(plainBytes)},
                                    std::pair<std::string, Bytes>{"bzip2", bzip2(plainBytes)}}) {
    const std::string wrappedPath = writeFile(stem + (kind == "gzip" ? ".gz" : ".bz2"), bytes);
    auto format = detectRadarFormat(wrappedPath);
    ASSERT_TRUE(format.ok()) << format.error();
    EXPECT_EQ(toString(*format), plain->format) << kind;
    const auto t0 = std::chrono::steady_clock::now();
    auto wrapped = readRadarVolume(wrappedPath, {});
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(wrapped.ok()) << wrapped.error();
    EXPECT_EQ(wrapped->compression, kind);
    EXPECT_EQ(wrapped->sourcePath, wrappedPath);
    std::size_t compared = 0;
    expectSameVolume(*plain, *wrapped, &compared);
    // The JSON names the wrapper; the text says it on the format line.
    EXPECT_NE(describeVolumeJson(*wrapped).find("\"compression\": \"" + kind + "\""), std::string::npos);
    EXPECT_NE(describeVolumeText(*wrapped).find("(" + kind + "-compressed file)"), std::string::npos);
    std::printf("[ compressed ] %s %s: %zu -> %zu bytes, %zu gate values identical, read in %.0f ms\n", stem.c_str(),
                kind.c_str(), plainBytes.size(), bytes.size(), compared, ms);
  }
}

TEST(Compression, SyntheticCfRadialReadsTheSameGzippedAndBzipped) {
  SyntheticRadarOptions o;
  o.elevationsDeg = {0.5, 1.5, 3.0};
  o.maxRangeMeters = 60000;
  const std::string path = outDir() + "/synthetic.nc";
  ASSERT_TRUE(writeSyntheticCfRadial(path, o).ok());
  checkWrappedReadsTheSame(path, "synthetic.nc");
}

TEST(Compression, RealFilesOfEveryFormatReadTheSame) {
  const std::string klbb = atmoglobe_test::testDataPath("radar_nexrad/KLBB20160601_150025_V06");
  const std::string bewid = atmoglobe_test::testDataPath("radar_odim/bewid.pvol.hdf");
  const std::string mll = atmoglobe_test::testDataPath("radar_cfradial/MLL2217907250U.003.nc");
  const std::string sigmet = atmoglobe_test::testDataPath("radar_sigmet/SUR210819000227.RAWKPJV");
  const std::string rainbow = atmoglobe_test::testDataPath("radar_rainbow/2013051000000600dBZ.vol");
  SKIP_WITHOUT_TEST_DATA(klbb, bewid, mll, sigmet, rainbow);
  checkWrappedReadsTheSame(klbb, "klbb");  // NEXRAD: its own bzip2 records inside the wrapper
  checkWrappedReadsTheSame(bewid, "bewid.pvol.hdf");
  checkWrappedReadsTheSame(mll, "mll.nc");
  checkWrappedReadsTheSame(sigmet, "sur.RAWKPJV");
  checkWrappedReadsTheSame(rainbow, "rainbow.vol");
}

TEST(Compression, GzippedGridIsAGridAndReadsTheSame) {
  SyntheticGridOptions o;
  o.nx = 40;
  o.ny = 30;
  o.levels = 10;
  o.times = 2;
  const std::string path = outDir() + "/grid.nc";
  ASSERT_TRUE(writeSyntheticGrid(path, o).ok());
  const std::string gz = writeFile("grid.nc.gz", gzip(readAll(path)));
  EXPECT_TRUE(isGridFile(gz));
  GridReadOptions ro;
  ro.timeIndex = 1;
  auto plain = readGridVolume(path, ro);
  auto wrapped = readGridVolume(gz, ro);
  ASSERT_TRUE(plain.ok()) << plain.error();
  ASSERT_TRUE(wrapped.ok()) << wrapped.error();
  EXPECT_EQ(plain->variable, wrapped->variable);
  EXPECT_EQ(plain->validTime, wrapped->validTime);
  ASSERT_EQ(plain->values.size(), wrapped->values.size());
  ASSERT_EQ(plain->heightAboveEllipsoidMeters.size(), wrapped->heightAboveEllipsoidMeters.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < plain->values.size(); ++i)
    differ += sameFloat(plain->values[i], wrapped->values[i]) ? 0 : 1;
  for (std::size_t i = 0; i < plain->heightAboveEllipsoidMeters.size(); ++i)
    differ += plain->heightAboveEllipsoidMeters[i] == wrapped->heightAboveEllipsoidMeters[i] ? 0 : 1;
  EXPECT_EQ(differ, 0u);
}

TEST(Compression, DetectsWrappersByMagicOnly) {
  const unsigned char gz[] = {0x1f, 0x8b, 8, 0};
  const unsigned char bz[] = {'B', 'Z', 'h', '9'};
  const unsigned char notBz[] = {'B', 'Z', 'h', '0'};  // block size digit must be 1..9
  const unsigned char ar2v[] = {'A', 'R', '2', 'V'};
  EXPECT_EQ(compressionOf(gz, 4), Compression::Gzip);
  EXPECT_EQ(compressionOf(bz, 4), Compression::Bzip2);
  EXPECT_EQ(compressionOf(notBz, 4), Compression::None);
  EXPECT_EQ(compressionOf(ar2v, 4), Compression::None);
  EXPECT_EQ(compressionOf(gz, 2), Compression::None);
}

TEST(Compression, ConcatenatedMembersAndStreamsAreOneContent) {
  Bytes a(1000), b(3000);
  for (std::size_t i = 0; i < a.size(); ++i) a[i] = static_cast<unsigned char>(i * 7);
  for (std::size_t i = 0; i < b.size(); ++i) b[i] = static_cast<unsigned char>(i * 13 + 1);
  Bytes joined = a;
  joined.insert(joined.end(), b.begin(), b.end());
  for (const bool useGzip : {true, false}) {
    Bytes twoMembers = useGzip ? gzip(a) : bzip2(a);
    const Bytes second = useGzip ? gzip(b) : bzip2(b);
    twoMembers.insert(twoMembers.end(), second.begin(), second.end());
    twoMembers.insert(twoMembers.end(), 512, 0);  // block padding after the last member: ignored
    auto out = decompress("x", twoMembers.data(), twoMembers.size(), useGzip ? Compression::Gzip : Compression::Bzip2);
    ASSERT_TRUE(out.ok()) << out.error();
    EXPECT_EQ(*out, joined);
  }
}

void expectError(const std::string& path, const std::vector<std::string>& parts) {
  auto v = readRadarVolume(path, {});
  ASSERT_FALSE(v.ok()) << path;
  for (const std::string& p : parts) EXPECT_NE(v.error().find(p), std::string::npos) << v.error();
}

TEST(Compression, BadCompressedInputGivesClearErrors) {
  SyntheticRadarOptions o;
  o.elevationsDeg = {0.5};
  o.maxRangeMeters = 30000;
  const std::string path = outDir() + "/small.nc";
  ASSERT_TRUE(writeSyntheticCfRadial(path, o).ok());
  const Bytes plain = readAll(path);
  const Bytes gz = gzip(plain), bz = bzip2(plain);

  // Truncated streams, at several points.
  for (double fraction : {0.1, 0.5, 0.9, 0.999}) {
    const auto cut = [&](const Bytes& b) {
      return Bytes(b.begin(), b.begin() + static_cast<long>(static_cast<double>(b.size()) * fraction));
    };
    const std::string g = writeFile("truncated.gz", cut(gz));
    expectError(g, {g + " (gzip): ", "ends early (truncated file?)"});
    const std::string z = writeFile("truncated.bz2", cut(bz));
    auto v = readRadarVolume(z, {});
    ASSERT_FALSE(v.ok());
    EXPECT_EQ(v.error().rfind(z + " (bzip2): ", 0), 0u) << v.error();
  }
  // Corrupt deflate data (bytes flipped in the middle).
  Bytes badGz = gz;
  for (std::size_t i = badGz.size() / 2; i < badGz.size() / 2 + 16; ++i) badGz[i] ^= 0x5a;
  const std::string corrupt = writeFile("corrupt.gz", badGz);
  auto v = readRadarVolume(corrupt, {});
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.error().rfind(corrupt + " (gzip): ", 0), 0u) << v.error();
  // A wrapper around something that is no radar format ("wrong magic inside").
  const std::string text = "just some text, not a radar volume\n";
  const std::string notRadar = writeFile("text.gz", gzip(Bytes(text.begin(), text.end())));
  expectError(notRadar, {notRadar + " (gzip): not a CfRadial", "Rainbow 5 inside the gzip wrapper", "6a 75 73 74"});
  const std::string notRadarBz = writeFile("text.bz2", bzip2(Bytes(text.begin(), text.end())));
  expectError(notRadarBz, {notRadarBz + " (bzip2): not a CfRadial", "inside the bzip2 wrapper"});
  // Trailing garbage after the stream.
  Bytes trailing = gz;
  const std::string junk = "garbage";
  trailing.insert(trailing.end(), junk.begin(), junk.end());
  const std::string trailingPath = writeFile("trailing.gz", trailing);
  expectError(trailingPath, {"after the end of the gzip stream"});
  // An empty .gz is not gzip (no magic): an unknown format, named as such.
  const std::string empty = writeFile("empty.gz", {});
  expectError(empty, {empty + ": not a CfRadial"});
}

TEST(Compression, ZipBombStopsAtTheLimit) {
  // 64 MiB of zeros: ~64 kB of gzip, ~50 bytes of bzip2. With a 16 MiB limit both must stop with
  // the limit named, having allocated at most the limit (the output only doubles up to it).
  const Bytes zeros(std::size_t{64} << 20, 0);
  const std::size_t limit = std::size_t{16} << 20;
  for (const bool useGzip : {true, false}) {
    const Bytes bomb = useGzip ? gzip(zeros, 9) : bzip2(zeros);
    auto out = decompress("bomb", bomb.data(), bomb.size(), useGzip ? Compression::Gzip : Compression::Bzip2, limit);
    ASSERT_FALSE(out.ok());
    EXPECT_NE(out.error().find("decompresses to more than 16 MiB"), std::string::npos) << out.error();
    std::printf("[ zip bomb ] %s: %zu bytes stopped at the 16 MiB limit\n", useGzip ? "gzip" : "bzip2", bomb.size());
  }
  // gzip states its size (ISIZE, mod 2^32): a stated size above the limit is refused before any
  // allocation when it is plausible (at most deflate's 1032:1 of the compressed size). Checked
  // with a hand-made trailer claiming 32 MiB on 64 KiB of incompressible data (~64 KiB of gzip):
  // refused at once with the limit named, where reading on would end in zlib's length check.
  Bytes noise(std::size_t{64} << 10);
  std::uint32_t x = 12345;
  for (unsigned char& c : noise) {
    x = x * 1103515245u + 12345u;
    c = static_cast<unsigned char>(x >> 24);
  }
  Bytes liar = gzip(noise, 9);
  auto honest = decompress("honest", liar.data(), liar.size(), Compression::Gzip, limit);
  ASSERT_TRUE(honest.ok()) << honest.error();
  EXPECT_EQ(*honest, noise);
  const std::uint32_t claimed = 32u << 20;
  for (int i = 0; i < 4; ++i)
    liar[liar.size() - 4 + static_cast<std::size_t>(i)] = static_cast<unsigned char>(claimed >> (8 * i));
  auto out = decompress("liar", liar.data(), liar.size(), Compression::Gzip, limit);
  ASSERT_FALSE(out.ok());
  EXPECT_NE(out.error().find("decompresses to more than 16 MiB"), std::string::npos) << out.error();
}

}  // namespace
}  // namespace atmoglobe::volume
