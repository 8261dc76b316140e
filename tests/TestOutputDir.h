#pragma once
// Where a test writes files: <build>/test-output/<executable>-<pid>/. ctest runs every test
// case as its own process, in parallel, so a fixed directory would be shared (and removed)
// by concurrent processes; one directory per process keeps them apart. It is removed when
// the process ends and every test passed; after a failure it stays for inspection.
// Force-included into every test source (tests/CMakeLists.txt).
#include <string>

namespace atmoglobe_test {
const std::string& outputDir();
/// An empty directory outputDir()/group/<current test name>, created afresh.
std::string freshTestDir(const std::string& group);
}  // namespace atmoglobe_test

#define ATMOGLOBE_TEST_OUTPUT_DIR (::atmoglobe_test::outputDir())
