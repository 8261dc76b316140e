#include "TestOutputDir.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace atmoglobe_test {

namespace {
std::string executableName() {
  std::ifstream comm("/proc/self/comm");
  std::string name;
  std::getline(comm, name);
  return name.empty() ? "test" : name;
}

void removeIfPassed() {
  const auto* unit = ::testing::UnitTest::GetInstance();
  if (unit && unit->Passed() && !std::getenv("ATMOGLOBE_KEEP_TEST_OUTPUT")) {
    std::error_code ec;
    std::filesystem::remove_all(outputDir(), ec);
  }
}
}  // namespace

const std::string& outputDir() {
  // Never destroyed: the atexit handler below still needs it after static destructors ran.
  static const std::string* dir = [] {
    auto* d = new std::string(std::string(ATMOGLOBE_TEST_OUTPUT_BASE) + "/" + executableName() + "-" +
                              std::to_string(static_cast<long>(::getpid())));
    std::filesystem::create_directories(*d);
    std::atexit(removeIfPassed);
    return d;
  }();
  return *dir;
}

std::string freshTestDir(const std::string& group) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = std::filesystem::path(outputDir()) / group / (info ? info->name() : "no-test");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace atmoglobe_test
