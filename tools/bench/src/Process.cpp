#include <atmoglobe/bench/Process.h>

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string_view>

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace atmoglobe::bench {

std::string ProgramExit::describe() const {
  // append, not "literal" + std::string: GCC 12 warns falsely (-Wrestrict) on the latter.
  std::string s;
  if (!started) return s.append("not started: ").append(error);
  if (signal != 0)
    return s.append("killed by signal ")
        .append(std::to_string(signal))
        .append(" (")
        .append(strsignal(signal))
        .append(")");
  return s.append("exit ").append(std::to_string(exitCode));
}

ProgramExit runProgram(const std::vector<std::string>& argv, bool quiet) {
  assert(!argv.empty());
  ProgramExit result;
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  } else {
    // The child writes to the same descriptors: what we printed must come out first.
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
  }
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    result.error = std::strerror(rc);
    return result;
  }
  int status = 0;
  pid_t waited = 0;
  struct rusage usage {};
  do {
    waited = wait4(pid, &status, 0, &usage);
  } while (waited < 0 && errno == EINTR);
  if (waited >= 0) result.maxRssKb = usage.ru_maxrss;
  if (waited < 0) {
    result.error = std::string("waitpid: ").append(std::strerror(errno));
    return result;
  }
  result.started = true;
  if (WIFEXITED(status)) {
    result.exitCode = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    result.signal = WTERMSIG(status);
  }
  // glibc before 2.24 (and some other C libraries) report a program they cannot execute as
  // exit 127 of a started child rather than as an error from posix_spawnp.
  if (result.exitCode == 127 && findProgram(argv[0]).empty()) {
    result.started = false;
    result.exitCode = -1;
    result.error = std::string(argv[0]).append(": no such program");
  }
  return result;
}

std::string findProgram(const std::string& name) {
  auto executable = [](const std::string& p) {
    struct stat st {};
    return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
  };
  if (name.empty()) return {};
  if (name.find('/') != std::string::npos) return executable(name) ? name : std::string();
  const char* path = std::getenv("PATH");
  const std::string_view dirs = path && *path ? path : "/usr/local/bin:/usr/bin:/bin";
  std::size_t pos = 0;
  while (pos <= dirs.size()) {
    const std::size_t colon = std::min(dirs.find(':', pos), dirs.size());
    const std::string_view dir = dirs.substr(pos, colon - pos);
    pos = colon + 1;
    std::string candidate;
    candidate.append(dir.empty() ? std::string_view(".") : dir).append("/").append(name);  // "": the current directory
    if (executable(candidate)) return candidate;
  }
  return {};
}

std::string displayCommand(const std::vector<std::string>& argv) {
  std::string out;
  for (const std::string& a : argv) {
    if (!out.empty()) out += ' ';
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789-_./=:,+@%") == std::string::npos;
    if (plain) {
      out += a;
      continue;
    }
    out += '\'';
    for (char c : a) {
      if (c == '\'') out.append("'\\''");
      else out += c;
    }
    out += '\'';
  }
  return out;
}

}  // namespace atmoglobe::bench
