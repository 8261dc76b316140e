// The one atomic-output helper (globe/AtomicFile.h): files, streamed files, directories, and the
// removal of temporaries that killed processes left behind.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "atmoglobe/globe/AtomicFile.h"

namespace atmoglobe::globe {
namespace {

namespace fs = std::filesystem;

fs::path freshDir() { return atmoglobe_test::freshTestDir("atomic_file"); }

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writePlain(const fs::path& p, const std::string& bytes) { std::ofstream(p, std::ios::binary) << bytes; }

std::size_t entryCount(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}));
}

// A pid that ran and has ended (a child that exited and was reaped): its temporaries are stale.
pid_t endedPid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  int status = 0;
  waitpid(pid, &status, 0);
  return pid;
}

TEST(AtomicFile, WriteReplacesWholeAndLeavesNothingElse) {
  const fs::path dir = freshDir();
  const std::string path = (dir / "out.csv").string();
  writePlain(path, "old contents");
  ASSERT_TRUE(writeFileAtomic(path, "new").ok());
  EXPECT_EQ(readAll(path), "new");
  EXPECT_EQ(entryCount(dir), 1u);
  // Onto a directory: an error naming it; the directory stays.
  Status s = writeFileAtomic(dir.string() + "/", "x");
  EXPECT_FALSE(s.ok());
  fs::create_directory(dir / "sub");
  s = writeFileAtomic((dir / "sub").string(), "x");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().find("sub: is a directory"), std::string::npos) << s.error();
}

TEST(AtomicFile, StreamedWriterPublishesOnlyOnCommit) {
  const fs::path dir = freshDir();
  const std::string path = (dir / "gates.csv").string();
  writePlain(path, "previous");
  {
    auto w = AtomicFileWriter::create(path);
    ASSERT_TRUE(w.ok()) << w.error();
    ASSERT_TRUE(w->write("a,b\n").ok());
    EXPECT_EQ(readAll(path), "previous");  // nothing visible before commit
    EXPECT_EQ(entryCount(dir), 2u);        // the file and its hidden temporary
  }                                        // abandoned: the temporary goes, the previous file stays
  EXPECT_EQ(readAll(path), "previous");
  EXPECT_EQ(entryCount(dir), 1u);
  auto w = AtomicFileWriter::create(path);
  ASSERT_TRUE(w.ok());
  ASSERT_TRUE(w->write("a,b\n").ok());
  ASSERT_TRUE(w->write("1,2\n").ok());
  ASSERT_TRUE(w->commit().ok());
  EXPECT_EQ(readAll(path), "a,b\n1,2\n");
  EXPECT_EQ(entryCount(dir), 1u);
  EXPECT_FALSE(w->commit().ok());  // once only
}

TEST(AtomicFile, StaleTemporariesOfEndedProcessesAreRemovedOthersKept) {
  const fs::path dir = freshDir();
  const std::string path = (dir / "view.png").string();
  const std::string dead = std::to_string(endedPid());
  writePlain(dir / (".view.png.tmp" + dead + "-0"), "half a png");      // a killed writer's file
  fs::create_directories(dir / (".view.png.tmp" + dead + "-1") / "0");  // a killed build's tree
  const std::string mine = ".view.png.tmp" + std::to_string(getpid()) + "-99";
  writePlain(dir / (".view.png.tmp" + dead + "-2.Ab3xYz"), "libzip's");  // libzip's temporary of ours
  writePlain(dir / mine, "in progress here");                            // a running writer's: kept
  writePlain(dir / ".view.png.tmpX-0", "not our pattern");               // not <pid>-<n>: kept
  writePlain(dir / (".view.png.tmp" + dead + "-3x"), "not our pattern either");
  writePlain(dir / ".other.png.tmp1-0", "another output");  // another output's: kept
  ASSERT_TRUE(writeFileAtomic(path, "png").ok());
  EXPECT_FALSE(fs::exists(dir / (".view.png.tmp" + dead + "-0")));
  EXPECT_FALSE(fs::exists(dir / (".view.png.tmp" + dead + "-1")));
  EXPECT_FALSE(fs::exists(dir / (".view.png.tmp" + dead + "-2.Ab3xYz")));
  EXPECT_TRUE(fs::exists(dir / mine));
  EXPECT_TRUE(fs::exists(dir / ".view.png.tmpX-0"));
  EXPECT_TRUE(fs::exists(dir / ".other.png.tmp1-0"));
  EXPECT_TRUE(fs::exists(dir / (".view.png.tmp" + dead + "-3x")));
  EXPECT_EQ(entryCount(dir), 5u);
}

TEST(AtomicFile, DirectoryIsSwappedWholeOrNotAtAll) {
  const fs::path dir = freshDir();
  const fs::path out = dir / "pyramid";
  // First publish: nothing there before.
  {
    auto staged = AtomicDirectory::create(out.string());
    ASSERT_TRUE(staged.ok()) << staged.error();
    fs::create_directories(fs::path(staged->dir()) / "0");
    ASSERT_TRUE(writeFileInStagedDirectory(staged->dir() + "/0/a.png", "A").ok());
    EXPECT_FALSE(fs::exists(out));
    ASSERT_TRUE(staged->publish().ok());
  }
  EXPECT_EQ(readAll(out / "0" / "a.png"), "A");
  // Abandoned rebuild: the old tree stays, the staged one goes.
  {
    auto staged = AtomicDirectory::create(out.string());
    ASSERT_TRUE(staged.ok());
    ASSERT_TRUE(writeFileInStagedDirectory(staged->dir() + "/b.png", "B").ok());
  }
  EXPECT_EQ(readAll(out / "0" / "a.png"), "A");
  EXPECT_FALSE(fs::exists(out / "b.png"));
  EXPECT_EQ(entryCount(dir), 1u);
  // Finished rebuild: the new tree replaces the old one entirely (a.png is gone).
  {
    auto staged = AtomicDirectory::create(out.string());
    ASSERT_TRUE(staged.ok());
    ASSERT_TRUE(writeFileInStagedDirectory(staged->dir() + "/b.png", "B").ok());
    ASSERT_TRUE(staged->publish().ok());
  }
  EXPECT_EQ(readAll(out / "b.png"), "B");
  EXPECT_FALSE(fs::exists(out / "0"));
  EXPECT_EQ(entryCount(dir), 1u);
  EXPECT_EQ(entryCount(out), 1u);
}

}  // namespace
}  // namespace atmoglobe::globe
