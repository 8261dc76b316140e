// Running programs without a shell (tools/bench: Process.h): exit status, signals, programs that
// do not exist, and arguments passed as they are (what a shell command string got wrong: paths
// with spaces or quotes).
#include <atmoglobe/bench/Process.h>

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

namespace atmoglobe::bench {
namespace {

TEST(BenchProcess, ExitStatusIsReported) {
  EXPECT_TRUE(runProgram({"true"}).succeeded());
  const ProgramExit f = runProgram({"false"});
  EXPECT_TRUE(f.started);
  EXPECT_FALSE(f.succeeded());
  EXPECT_EQ(f.exitCode, 1);
  EXPECT_EQ(f.describe(), "exit 1");
  EXPECT_EQ(runProgram({"sh", "-c", "exit 3"}).exitCode, 3);
}

TEST(BenchProcess, DeathBySignalIsReported) {
  const ProgramExit k = runProgram({"sh", "-c", "kill -KILL $$"});
  EXPECT_TRUE(k.started);
  EXPECT_FALSE(k.succeeded());
  EXPECT_EQ(k.signal, SIGKILL);
  EXPECT_EQ(k.describe().rfind("killed by signal 9", 0), 0u) << k.describe();
}

TEST(BenchProcess, MissingProgramIsNotStarted) {
  const ProgramExit m = runProgram({"atmoglobe-no-such-program-xyz", "arg"});
  EXPECT_FALSE(m.started);
  EXPECT_FALSE(m.succeeded());
  EXPECT_FALSE(m.error.empty());
  EXPECT_EQ(m.describe().rfind("not started: ", 0), 0u) << m.describe();
  EXPECT_FALSE(runProgram({"/nonexistent/dir/program"}).started);
}

// The argument reaches the program byte for byte: spaces, both quotes, $, ;, a newline.
TEST(BenchProcess, ArgumentsArePassedAsTheyAre) {
  const std::string tricky = "a b'c \"d\" $HOME; rm -rf x\nend";
  EXPECT_TRUE(runProgram({"sh", "-c", "test \"$1\" = \"$2\"", "sh", tricky, tricky}).succeeded());
  EXPECT_FALSE(runProgram({"sh", "-c", "test \"$1\" = \"$2\"", "sh", tricky, "a b'c"}).succeeded());

  // And a file whose path has a space and a quote is written where it says.
  const std::filesystem::path dir = atmoglobe_test::freshTestDir("process");
  const std::filesystem::path file = dir / "it's a file.txt";
  EXPECT_TRUE(runProgram({"sh", "-c", "printf ok > \"$1\"", "sh", file.string()}).succeeded());
  std::ifstream in(file);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "ok");
}

TEST(BenchProcess, QuietRunsWriteNothingOfTheirs) {
  // Quiet: stdout and stderr to /dev/null; what the child writes must not reach ours.
  testing::internal::CaptureStdout();
  EXPECT_TRUE(runProgram({"sh", "-c", "echo not-to-be-seen; echo nor-this >&2"}, true).succeeded());
  EXPECT_EQ(testing::internal::GetCapturedStdout().find("not-to-be-seen"), std::string::npos);
}

TEST(BenchProcess, FindProgramSearchesPath) {
  const std::string sh = findProgram("sh");
  ASSERT_FALSE(sh.empty());
  EXPECT_EQ(sh.front(), '/');
  EXPECT_TRUE(findProgram("atmoglobe-no-such-program-xyz").empty());
  EXPECT_EQ(findProgram(sh), sh);  // a path is checked, not searched
  EXPECT_TRUE(findProgram("/nonexistent/sh").empty());
  EXPECT_TRUE(findProgram("").empty());
}

TEST(BenchProcess, DisplayCommandQuotesWhereNeeded) {
  EXPECT_EQ(displayCommand({"xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "/usr/bin/python3", "/a b/it's.py"}),
            "xvfb-run -a -s '-screen 0 1280x1024x24' /usr/bin/python3 '/a b/it'\\''s.py'");
  EXPECT_EQ(displayCommand({"x", ""}), "x ''");
}

}  // namespace
}  // namespace atmoglobe::bench
