#pragma once
// Real sample data for the tests (radar files, station lists) that the repository does not ship.
// One setting finds them: $ATMOGLOBE_TEST_DATA, else <source dir>/../shared/data.
//
// A test that reads them starts with SKIP_WITHOUT_TEST_DATA(path, ...): when a file is absent
// the test is skipped with the reason, or fails when $ATMOGLOBE_REQUIRE_TEST_DATA is set (CI,
// through test.sh). Such tests are listed in tests/CMakeLists.txt, which gives them the ctest
// label `realdata`; the macro fails a test that ctest runs without that label, so the list
// cannot silently fall behind. The CLI tests use the same setting (tests/tools/TestData.cmake).
// Force-included into every test source (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <string>

namespace atmoglobe_test {

/// The sample data directory: $ATMOGLOBE_TEST_DATA when set and non-empty, else the default
/// compiled in (ATMOGLOBE_TEST_DATA_DEFAULT, <source dir>/../shared/data).
inline const std::string& testDataDir() {
  static const std::string dir = [] {
    const char* env = std::getenv("ATMOGLOBE_TEST_DATA");
    return std::string(env && *env ? env : ATMOGLOBE_TEST_DATA_DEFAULT);
  }();
  return dir;
}

/// testDataDir() + "/" + relative, e.g. testDataPath("radar_odim/bewid.pvol.hdf").
inline std::string testDataPath(const std::string& relative) { return testDataDir() + "/" + relative; }

inline bool envFlagSet(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::string(v) != "0";
}

struct TestDataCheck {
  bool fail = false;
  std::string message;  ///< empty: every file is there and the test may run
};

/// Whether a test may read `paths` (absolute, under testDataDir()), and if not, why.
inline TestDataCheck checkTestData(std::initializer_list<std::string> paths) {
  // ctest sets ATMOGLOBE_TEST_REALDATA=1 on tests labelled realdata and 0 on the others.
  const char* label = std::getenv("ATMOGLOBE_TEST_REALDATA");
  if (label && std::string(label) == "0")
    return {true,
            "this test reads real sample data but ctest runs it without the realdata label: "
            "add it to the realdata list of its executable in tests/CMakeLists.txt"};
  for (const std::string& p : paths) {
    if (std::filesystem::exists(p)) continue;
    const std::string where = std::filesystem::is_directory(testDataDir()) ? p : testDataDir();
    std::string message = "real sample data not found at " + where + " (set ATMOGLOBE_TEST_DATA)";
    const bool required = envFlagSet("ATMOGLOBE_REQUIRE_TEST_DATA");
    if (required) message += "; ATMOGLOBE_REQUIRE_TEST_DATA is set, so this is a failure";
    return {required, message};
  }
  return {};
}

}  // namespace atmoglobe_test

/// First line of a test that reads real sample data: skips it (or fails it, see above) unless
/// every one of the given paths exists.
#define SKIP_WITHOUT_TEST_DATA(...)                                                                        \
  do {                                                                                                     \
    const ::atmoglobe_test::TestDataCheck testDataCheck_ = ::atmoglobe_test::checkTestData({__VA_ARGS__}); \
    if (testDataCheck_.fail) GTEST_FAIL() << testDataCheck_.message;                                       \
    if (!testDataCheck_.message.empty()) GTEST_SKIP() << testDataCheck_.message;                           \
  } while (false)
