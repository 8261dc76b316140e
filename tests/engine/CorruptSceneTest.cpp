// Scene JSON in the bad-input suite (docs/robustness.md "Bad-input suite"): a
// scene truncated at 32 offsets and bit-flipped, and out-of-range values (latitudes beyond 90,
// numbers beyond double, wrong types, a frame size claiming terabytes). Each case runs in a child
// with a time limit and a memory cap (tests/BoundedRun.h) and must parse, or fail with an error
// naming the scene; never crash, hang or allocate for what it claims. Parsing only: the validation
// rules of each field belong to the scene tests.
#include <atmoglobe/engine/Scene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <random>
#include <string>

#include "BoundedRun.h"

using namespace atmoglobe;
using atmoglobe_test::BoundedOutcome;

namespace {

// A scene without files (so that the parser's checks, not missing data, decide), with every kind
// of value: camera angles and height, field of view, size, markers, a time.
const std::string kScene = R"({
  "camera": {"lat_deg": 34.45, "lon_deg": -98.35, "height_m": 50000.0,
             "heading_deg": 40.0, "pitch_deg": -28.0, "roll_deg": 0.0},
  "fov_deg": 45.0,
  "size": [320, 200],
  "markers": [{"lat_deg": 35.33, "lon_deg": -97.28, "label": "KTLX"}]
})";

std::optional<std::string> parse(const std::string& json, const std::string& name) {
  auto s = engine::parseSceneJson(json, name, ".", ".");
  return s ? std::nullopt : std::optional<std::string>(s.error());
}

/// Time: a parse takes well under 10 ms; 10 s is room for sanitizers. Memory: the JSON document
/// and the scene are a few kB; 64 MiB is the same library allowance as the other readers'.
BoundedOutcome runCase(const std::string& what, const std::string& name, const std::string& json, int& errors) {
  const std::size_t cap = std::size_t{64} << 20;
  BoundedOutcome o = atmoglobe_test::runBounded([&] { return parse(json, name); }, 10, cap);
  EXPECT_TRUE(o.kind == BoundedOutcome::Kind::Read || o.kind == BoundedOutcome::Kind::Error)
      << what << ": " << atmoglobe_test::toString(o.kind) << " (" << o.message << ")\n"
      << o.backtrace;
  EXPECT_LE(static_cast<std::size_t>(std::max(0L, o.rssGrowthKb)) * 1024, cap) << what;
  if (o.kind == BoundedOutcome::Kind::Error) {
    ++errors;
    EXPECT_NE(o.message.find(name), std::string::npos) << what << ": the error does not name the scene: " << o.message;
  }
  return o;
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

}  // namespace

TEST(CorruptInput, SceneJsonEveryCase) {
  ASSERT_FALSE(parse(kScene, "good.json")) << *parse(kScene, "good.json");
  int errors = 0, cases = 0;
  for (std::size_t k = 0; k < 32; ++k, ++cases) {
    const std::size_t cut = kScene.size() * k / 32;
    runCase("truncated at " + std::to_string(cut), "cut" + std::to_string(cut) + ".json", kScene.substr(0, cut),
            errors);
  }
  std::mt19937 rng(19);
  std::uniform_int_distribution<std::size_t> at(0, kScene.size() - 1);
  std::uniform_int_distribution<int> bit(0, 7), count(1, 4);
  for (int i = 0; i < 24; ++i, ++cases) {
    std::string s = kScene;
    for (int n = count(rng); n > 0; --n) {
      const std::size_t p = at(rng);
      s[p] = static_cast<char>(s[p] ^ (1 << bit(rng)));
    }
    runCase("bits flipped", "flip" + std::to_string(i) + ".json", s, errors);
  }
  // Every one of these must be refused, naming the scene.
  const std::pair<const char*, std::string> refused[] = {
      {"camera latitude 95", replaced(kScene, "\"lat_deg\": 34.45", "\"lat_deg\": 95")},
      {"marker latitude -91", replaced(kScene, "\"lat_deg\": 35.33", "\"lat_deg\": -91")},
      {"NaN (not JSON)", replaced(kScene, "\"lon_deg\": -98.35", "\"lon_deg\": NaN")},
      {"height beyond double", replaced(kScene, "50000.0", "1e999")},
      {"latitude of type string", replaced(kScene, "\"lat_deg\": 34.45", "\"lat_deg\": \"north\"")},
      {"size claiming 1e12 x 1e12 pixels", replaced(kScene, "[320, 200]", "[1000000000000, 1000000000000]")},
      {"size of negative pixels", replaced(kScene, "[320, 200]", "[-320, 200]")},
      {"field of view 0", replaced(kScene, "\"fov_deg\": 45.0", "\"fov_deg\": 0")},
  };
  for (const auto& [what, json] : refused) {
    ++cases;
    const std::string name = std::string("refused-").append(std::to_string(cases)).append(".json");
    const BoundedOutcome o = runCase(what, name, json, errors);
    EXPECT_EQ(o.kind, BoundedOutcome::Kind::Error) << what << " was " << atmoglobe_test::toString(o.kind);
    std::printf("[ refused  ] scene JSON, %s: %s\n", what, o.message.c_str());
  }
  std::printf("[ tally    ] scene JSON: %d cases, %d errors\n", cases, errors);
}
