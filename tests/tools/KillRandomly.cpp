// atmoglobe_kill_test ATMOGLOBE WORKDIR EARTH_IMAGE [SEED [KILLS_PER_COMMAND]]
//
// "Nothing lost" (docs/robustness.md): runs `atmoglobe export-cones` (.glb and .kmz), `tiles` (a
// pyramid directory), `convert` (NRRD) and `render` (PNG) over an existing output and kills each
// with SIGKILL at random moments (seeded std::mt19937; delays uniform over 0..1.2 x the time a
// complete run of that command took here). After every kill the output must be byte for byte the
// previous output (A) or, when the kill came after the new one was published, the complete new
// output (B) -- never a mixture, a truncation or nothing -- and no other visible file may appear
// beside it. At the end one complete run must leave no temporary of a killed run behind (they are
// hidden ".NAME.tmp<pid>-<n>" entries, removed by the next write of the same output).
// Exit 0 when every check passed; prints one line per kill and a summary per command.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
  if (!ok) {
    std::printf("FAIL: %s\n", what.c_str());
    ++failures;
  }
}

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Every entry under `dir` (recursive): relative path -> bytes ("<dir>" for directories).
using Tree = std::map<std::string, std::string>;

Tree snapshot(const fs::path& dir) {
  Tree t;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string rel = fs::relative(it->path(), dir).string();
    t[rel] = it->is_directory() ? std::string("<dir>") : readAll(it->path());
  }
  return t;
}

// The visible part of a tree: entries whose name (any component) starts with '.' are left out.
Tree visible(const Tree& t) {
  Tree v;
  for (const auto& [rel, bytes] : t) {
    bool hidden = false;
    for (const auto& part : fs::path(rel)) hidden = hidden || part.string().rfind('.', 0) == 0;
    if (!hidden) v[rel] = bytes;
  }
  return v;
}

std::size_t hiddenCount(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.path().filename().string().rfind('.', 0) == 0;
  return n;
}

struct Outcome {
  bool signaled = false;
  int exitCode = 0;
};

// Runs argv; with killAfter >= 0, sends SIGKILL after that many seconds unless it ended before.
Outcome run(const std::vector<std::string>& argv, double killAfterSeconds) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid < 0) {
    std::perror("fork");
    std::exit(2);
  }
  if (pid == 0) {
    // The child's own output is not part of the test: keep the log short (exit codes are checked).
    if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr)) _exit(126);
    execv(args[0], args.data());
    _exit(127);
  }
  int status = 0;
  if (killAfterSeconds >= 0) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(killAfterSeconds);
    for (;;) {
      const pid_t done = waitpid(pid, &status, WNOHANG);
      if (done == pid) return {WIFSIGNALED(status) != 0, WIFEXITED(status) ? WEXITSTATUS(status) : -1};
      if (Clock::now() >= deadline) break;
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    kill(pid, SIGKILL);
  }
  waitpid(pid, &status, 0);
  return {WIFSIGNALED(status) != 0, WIFEXITED(status) ? WEXITSTATUS(status) : -1};
}

struct Case {
  std::string name;
  std::string output;                     // file or directory name inside the case's directory
  std::vector<std::string> argsA, argsB;  // {OUT} stands for the output path
};

std::vector<std::string> withOutput(const std::string& exe, const std::vector<std::string>& args, const fs::path& out) {
  std::vector<std::string> v{exe};
  for (const auto& a : args) v.push_back(a == "{OUT}" ? out.string() : a);
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s ATMOGLOBE WORKDIR EARTH_IMAGE [SEED [KILLS_PER_COMMAND]]\n", argv[0]);
    return 2;
  }
  const std::string exe = fs::absolute(argv[1]).string();
  const fs::path work = fs::absolute(argv[2]);
  const std::string earth = argv[3];
  const unsigned seed = argc > 4 ? static_cast<unsigned>(std::strtoul(argv[4], nullptr, 10)) : 20261125u;
  const int killsPerCommand = argc > 5 ? std::atoi(argv[5]) : 5;
  std::mt19937 rng(seed);
  // Exports that embed a time (COLLADA <created>, zip entry times) use this instead of "now", so a
  // complete re-export is byte-identical and "the new output" can be recognised.
  setenv("SOURCE_DATE_EPOCH", "1588334400", 1);
  std::printf("seed %u, %d kills per command\n", seed, killsPerCommand);

  fs::remove_all(work);
  fs::create_directories(work / "in");
  const std::string radar = (work / "in" / "synthetic.nc").string(), grid = (work / "in" / "grid.nc").string();
  if (run({exe, "synth", "-o", radar}, -1).exitCode != 0 ||
      run({exe, "synth", "--grid", "--grid-size", "80,60,12,3", "-o", grid}, -1).exitCode != 0) {
    std::printf("FAIL: cannot make the synthetic inputs\n");
    return 1;
  }

  const std::vector<Case> cases = {
      // Two sweeps of the synthetic volume keep each export under a second or two.
      {"export-cones-glb",
       "cones.glb",
       {"export-cones", radar, "--sweeps", "0-1", "-o", "{OUT}"},
       {"export-cones", radar, "--sweeps", "0-1", "--max-range", "60", "-o", "{OUT}"}},
      {"export-cones-kmz",
       "cones.kmz",
       {"export-cones", radar, "--sweeps", "0-1", "-o", "{OUT}"},
       {"export-cones", radar, "--sweeps", "0-1", "--max-range", "60", "-o", "{OUT}"}},
      {"tiles",
       "pyramid",
       {"tiles", earth, "--max-level", "1", "-o", "{OUT}"},
       {"tiles", earth, "--max-level", "2", "-o", "{OUT}"}},
      {"convert",
       "grid.nrrd",
       {"convert", grid, "--size", "20,25,8", "-o", "{OUT}"},
       {"convert", grid, "--size", "40,30,12", "-o", "{OUT}"}},
      {"render",
       "view.png",
       {"render", "--radar", radar, "--camera", "34.35,-97.0,4.5e4,330,-28,0", "--size", "64x36", "-o", "{OUT}"},
       {"render", "--radar", radar, "--camera", "34.35,-97.0,6e4,300,-35,0", "--size", "64x36", "-o", "{OUT}"}},
  };

  int totalKills = 0, totalMidWrite = 0;
  for (const Case& c : cases) {
    const fs::path dir = work / c.name, out = dir / c.output;
    const fs::path refDir = work / (c.name + "-B");
    fs::create_directories(dir);
    fs::create_directories(refDir);
    // B: the complete new output, made once elsewhere under the same name.
    const auto t0 = Clock::now();
    check(run(withOutput(exe, c.argsB, refDir / c.output), -1).exitCode == 0, c.name + ": the B run failed");
    const double secondsB = std::chrono::duration<double>(Clock::now() - t0).count();
    const Tree treeB = snapshot(refDir);
    // A: the previous output, in place.
    check(run(withOutput(exe, c.argsA, out), -1).exitCode == 0, c.name + ": the A run failed");
    const Tree treeA = snapshot(dir);
    check(!treeA.empty() && treeA != treeB, c.name + ": A and B must be different non-empty outputs");

    std::uniform_real_distribution<double> delay(0.0, 1.2 * secondsB);
    int keptA = 0, becameB = 0, killed = 0;
    for (int k = 0; k < killsPerCommand; ++k) {
      const double d = delay(rng);
      const Outcome o = run(withOutput(exe, c.argsB, out), d);
      const Tree now = visible(snapshot(dir));
      const bool isA = now == treeA, isB = now == treeB;
      keptA += isA;
      becameB += isB;
      killed += o.signaled;
      std::printf("  %s kill %d at %.3f s: %s, output %s\n", c.name.c_str(), k + 1, d,
                  o.signaled ? "killed" : "had finished",
                  isA   ? "= previous (A)"
                  : isB ? "= new (B)"
                        : "MIXED");
      check(isA || isB, c.name + ": after a kill at " + std::to_string(d) +
                            " s the visible output is neither the previous nor the new one");
      check(o.signaled || isB, c.name + ": a run that finished must leave the new output");
      // Back to A, so that every kill can show A kept.
      if (isB) check(run(withOutput(exe, c.argsA, out), -1).exitCode == 0, c.name + ": re-running A failed");
    }
    const std::size_t leftovers = hiddenCount(dir);
    // One complete run removes what the killed ones left.
    check(run(withOutput(exe, c.argsB, out), -1).exitCode == 0, c.name + ": the final run failed");
    check(snapshot(dir) == treeB, c.name +
                                      ": after a complete run the directory holds exactly the new output "
                                      "(no temporary of a killed run left)");
    std::printf(
        "%s: %d kills (%d while running), %d left the previous output, %d the new one; "
        "%zu hidden temporaries left by the kills, 0 after the next complete run; a run took %.2f s\n",
        c.name.c_str(), killsPerCommand, killed, keptA, becameB, leftovers, secondsB);
    totalKills += killsPerCommand;
    totalMidWrite += killed;
  }
  // Too few kills landing while a command ran would make the test meaningless.
  check(totalMidWrite * 2 >= totalKills, "fewer than half the kills landed while a command ran");
  std::printf("%d kills, %d while running, %d failures\n", totalKills, totalMidWrite, failures);
  return failures == 0 ? 0 : 1;
}
