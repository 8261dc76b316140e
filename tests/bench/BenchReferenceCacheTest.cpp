// The reference cache (tools/bench: ReferenceCache.h): the key's text and its file name (which
// must not change: existing caches would be orphaned), the write / read round trip, and every
// kind of bad file read as a miss, not a crash.
#include <atmoglobe/bench/ReferenceCache.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace atmoglobe::bench {
namespace {

namespace fs = std::filesystem;

BenchVolume klbbVolume() {
  BenchVolume v;
  v.key = "KLBB";
  v.path = "/data/radar_nexrad/KLBB20160601_150025_V06";
  v.polar.fieldName = "REF";
  return v;
}

BenchView viewOf(const BenchVolume& v) {
  BenchView view;
  view.name = "KLBB-oblique";
  view.volume = &v;
  view.pose.latDeg = 31.85;
  view.pose.lonDeg = -101.8142;
  view.pose.heightMeters = 100000.0;
  view.pose.headingDeg = 180.5;
  view.pose.pitchDeg = -25.25;
  view.fovYDeg = 50.0;
  return view;
}

volume::VolumeImage testImage(int w, int h, double seed) {
  volume::VolumeImage img;
  img.widthPx = w;
  img.heightPx = h;
  for (int i = 0; i < w * h; ++i)
    img.rgbaPremultiplied.push_back(glm::dvec4(seed + i, 0.1 * i, 1.0 / (i + 3.0), 0.5 + 1e-12 * i));
  return img;
}

bool sameBits(const volume::VolumeImage& a, const volume::VolumeImage& b) {
  return a.widthPx == b.widthPx && a.heightPx == b.heightPx &&
         a.rgbaPremultiplied.size() == b.rgbaPremultiplied.size() &&
         std::memcmp(a.rgbaPremultiplied.data(), b.rgbaPremultiplied.data(),
                     a.rgbaPremultiplied.size() * sizeof(glm::dvec4)) == 0;
}

// The key as docs/bench-volume.md lists its parts, and its file name. Expected values computed
// independently (Python: the key typed out, 64-bit FNV-1a with offset basis 1469598103934665603
// and prime 1099511628211). With the standard basis 14695981039346656037 the name would be
// 72cb30a6f4a7b1b0.ref: the bench keeps the one it has always used so that existing caches
// stay valid.
TEST(BenchReferenceCache, KeyTextAndFileNameAreStable) {
  const BenchVolume v = klbbVolume();
  const BenchView view = viewOf(v);
  const std::string key = referenceKey(view, 160, 90, referenceSettings(volume::VolumeRenderMode::Dvr, 100.0));
  EXPECT_EQ(key,
            "ref-v1|/data/radar_nexrad/KLBB20160601_150025_V06|REF|31.85,-101.8142,100000,180.5,-25.25,0|fov 50|"
            "160x90|dvr|linear|step 100|iso 40|term 0.99|tf NWS reflectivity,10,60,0.8,1000|no-occlusion");
  EXPECT_EQ(referenceFileName(key), "192b87dd6277ace2.ref");
  EXPECT_EQ(fnv1a(""), 1469598103934665603ull);  // the (non-standard) offset basis itself

  // Every part of the key matters.
  EXPECT_NE(referenceKey(view, 160, 91, referenceSettings(volume::VolumeRenderMode::Dvr, 100.0)), key);
  EXPECT_NE(referenceKey(view, 160, 90, referenceSettings(volume::VolumeRenderMode::Mip, 100.0)), key);
  EXPECT_NE(referenceKey(view, 160, 90, referenceSettings(volume::VolumeRenderMode::Dvr, 50.0)), key);
  BenchView moved = view;
  moved.pose.headingDeg += 1e-6;
  EXPECT_NE(referenceKey(moved, 160, 90, referenceSettings(volume::VolumeRenderMode::Dvr, 100.0)), key);
}

TEST(BenchReferenceCache, WriteThenReadGivesTheSameImage) {
  const fs::path dir = atmoglobe_test::freshTestDir("reference-cache");
  const std::string key = "ref-v1|a key";
  const fs::path file = dir / referenceFileName(key);
  const volume::VolumeImage img = testImage(7, 3, 0.25);
  ASSERT_TRUE(writeCachedReference(file, key, img));
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));  // renamed into place
  std::optional<volume::VolumeImage> back = readCachedReference(file, key);
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(sameBits(*back, img));  // doubles stored as they are: bit-identical

  // Rewritten under the same key: the new image.
  const volume::VolumeImage img2 = testImage(2, 5, 9.0);
  ASSERT_TRUE(writeCachedReference(file, key, img2));
  back = readCachedReference(file, key);
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(sameBits(*back, img2));
}

TEST(BenchReferenceCache, AnotherKeyOrABadFileIsAMiss) {
  const fs::path dir = atmoglobe_test::freshTestDir("reference-cache");
  const std::string key = "ref-v1|the key";
  const fs::path file = dir / "cached.ref";
  const volume::VolumeImage img = testImage(4, 4, 1.0);
  ASSERT_TRUE(writeCachedReference(file, key, img));
  ASSERT_TRUE(readCachedReference(file, key).has_value());

  EXPECT_FALSE(readCachedReference(file, "ref-v1|another key").has_value());  // a hash collision
  EXPECT_FALSE(readCachedReference(file, "ref-v1|the ke").has_value());       // a prefix
  EXPECT_FALSE(readCachedReference(dir / "missing.ref", key).has_value());

  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto writeBytes = [&](const std::string& name, const std::string& content) {
    const fs::path p = dir / name;
    std::ofstream(p, std::ios::binary) << content;
    return p;
  };
  // Truncated anywhere: in the header, in the key, in the size, in the pixels, one byte short.
  for (std::size_t n : {std::size_t{0}, std::size_t{2}, std::size_t{4}, std::size_t{10}, 4 + key.size() + 5,
                        bytes.size() / 2, bytes.size() - 1}) {
    EXPECT_FALSE(readCachedReference(writeBytes("truncated.ref", bytes.substr(0, n)), key).has_value()) << n;
  }
  // A key length far beyond the limit (would be a 4 GB allocation if believed).
  std::string huge = bytes;
  const std::uint32_t big = 0xFFFFFFFFu;
  std::memcpy(huge.data(), &big, sizeof big);
  EXPECT_FALSE(readCachedReference(writeBytes("huge-key.ref", huge), key).has_value());
  // Sizes zero, negative, or beyond 8192.
  for (std::int32_t width : {0, -4, 8193, 1 << 30}) {
    std::string bad = bytes;
    std::memcpy(bad.data() + 4 + key.size(), &width, sizeof width);
    EXPECT_FALSE(readCachedReference(writeBytes("bad-size.ref", bad), key).has_value()) << width;
  }
  // Noise.
  EXPECT_FALSE(readCachedReference(writeBytes("noise.ref", std::string(1000, '\xA5')), key).has_value());
  // A directory where the file should be.
  fs::create_directories(dir / "dir.ref");
  EXPECT_FALSE(readCachedReference(dir / "dir.ref", key).has_value());
  // Writing where it cannot (no such directory) reports it and leaves nothing.
  EXPECT_FALSE(writeCachedReference(dir / "no-such-dir" / "x.ref", key, img));
}

// The store finds what was written under the key and name it computes itself: no rendering.
TEST(BenchReferenceCache, StoreReadsTheCacheBeforeRendering) {
  const fs::path dir = atmoglobe_test::freshTestDir("reference-cache");
  const BenchVolume v = klbbVolume();  // no layout: rendering it would be an error
  const BenchView view = viewOf(v);
  const volume::VolumeRenderSettings s = referenceSettings(volume::VolumeRenderMode::Iso, 100.0);
  const std::string key = referenceKey(view, 16, 9, s);
  const volume::VolumeImage img = testImage(16, 9, 3.0);
  ASSERT_TRUE(writeCachedReference(dir / referenceFileName(key), key, img));
  ReferenceStore store;
  store.dir = dir;
  const volume::VolumeImage got = store.get(view, 16, 9, s);
  EXPECT_TRUE(sameBits(got, img));
  EXPECT_EQ(store.cached, 1);
  EXPECT_EQ(store.rendered, 0);
}

}  // namespace
}  // namespace atmoglobe::bench
