#pragma once
// Running a program without a shell: argv goes to the program as it is (paths with spaces or
// quotes need no quoting), the caller waits for it and gets its exit status.
#include <string>
#include <vector>

namespace atmoglobe::bench {

struct ProgramExit {
  bool started = false;  ///< false: it could not be started (not found, not executable)
  int exitCode = -1;     ///< exit status when it exited normally, else -1
  int signal = 0;        ///< the signal that ended it, else 0
  std::string error;     ///< why it could not be started (strerror)
  long maxRssKb = 0;     ///< the child's peak resident set (ru_maxrss from wait4, KiB)

  bool succeeded() const { return started && signal == 0 && exitCode == 0; }
  /// "exit 3", "killed by signal 9 (Killed)", "not started: No such file or directory".
  std::string describe() const;
};

/// Runs argv[0] (searched in PATH when it has no '/') with `argv` through posix_spawnp and
/// waits for it. `quiet`: its stdout and stderr go to /dev/null; otherwise it shares ours
/// (flushed before it starts). Precondition: argv not empty.
ProgramExit runProgram(const std::vector<std::string>& argv, bool quiet = false);

/// The path of an executable `name` in $PATH (what `command -v` prints), or "" when there is
/// none. A name with a '/' is returned as it is if it is executable.
std::string findProgram(const std::string& name);

/// argv for display, each argument single-quoted where it needs it (not for running).
std::string displayCommand(const std::vector<std::string>& argv);

}  // namespace atmoglobe::bench
