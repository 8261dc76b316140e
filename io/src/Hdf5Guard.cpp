#include <atmoglobe/io/Hdf5Guard.h>
#include <atmoglobe/io/NetcdfFile.h>
#include <atmoglobe/io/NetcdfLock.h>

#include <netcdf.h>
#include <netcdf_mem.h>

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

// A libFuzzer (or sanitizer) death callback would write a crash artefact from the child; the
// child clears it. Weak: absent in normal builds.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace atmoglobe::io {

namespace {
constexpr unsigned char kSignature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

// Exit statuses of the child.
constexpr int kChildPassed = 0;
constexpr int kChildOpenFailed = 3;
constexpr int kChildPassedDamaged = 4;  // walked to the end, but library calls failed on the way

// Bounds of the child's walk: the readers themselves refuse more, and a corrupt file must not
// make the child allocate what the file cannot hold (the parent's checks do not run here).
constexpr std::size_t kMaxAttributeBytes = std::size_t{1} << 20;
constexpr std::size_t kMaxVariableBytes = std::size_t{1} << 30;
constexpr int kMaxGroupDepth = 64;

/// Library calls of the child's walk that failed: it only asks for what the file lists, so any
/// failure means the file is damaged (reported to the parent, see Hdf5GuardOutcome::damaged).
int gFailedCalls = 0;
bool ok(int status) {
  if (status != NC_NOERR) ++gFailedCalls;
  return status == NC_NOERR;
}

void walkAttributes(int group, int varId, int count) {
  std::vector<unsigned char> buffer;
  for (int a = 0; a < count; ++a) {
    char name[NC_MAX_NAME + 1] = {};
    if (!ok(nc_inq_attname(group, varId, a, name))) continue;
    nc_type type = NC_NAT;
    std::size_t length = 0;
    if (!ok(nc_inq_att(group, varId, name, &type, &length))) continue;
    if (type == NC_STRING) {
      if (length == 0 || length > kMaxAttributeBytes / sizeof(char*)) continue;
      std::vector<char*> strings(length, nullptr);
      if (ok(nc_get_att_string(group, varId, name, strings.data()))) nc_free_string(length, strings.data());
      continue;
    }
    const std::size_t bytes = ncTypeSize(type);
    if (bytes == 0 || length == 0 || length > kMaxAttributeBytes / bytes) continue;
    buffer.resize(length * bytes);
    ok(nc_get_att(group, varId, name, buffer.data()));
  }
}

void walkVariableValues(int group, int varId, nc_type type, int rank, const int* dimIds) {
  std::size_t count = 1;
  for (int d = 0; d < rank; ++d) {
    std::size_t length = 0;
    if (!ok(nc_inq_dimlen(group, dimIds[d], &length))) return;
    if (length != 0 && count > kMaxVariableBytes / length) return;
    count *= length;
  }
  if (count == 0) return;
  if (type == NC_STRING) {
    if (count > kMaxAttributeBytes) return;
    std::vector<char*> strings(count, nullptr);
    if (ok(nc_get_var_string(group, varId, strings.data()))) nc_free_string(count, strings.data());
    return;
  }
  const std::size_t bytes = ncTypeSize(type);
  if (bytes == 0 || count > kMaxVariableBytes / bytes) return;
  std::vector<unsigned char> values(count * bytes);
  ok(nc_get_var(group, varId, values.data()));
}

void walkGroup(int group, bool readValues, int depth) {
  if (depth > kMaxGroupDepth) return;
  int dimCount = 0;
  if (ok(nc_inq_dimids(group, &dimCount, nullptr, 0)) && dimCount > 0) {
    std::vector<int> dims(static_cast<std::size_t>(dimCount));
    if (ok(nc_inq_dimids(group, &dimCount, dims.data(), 0)))
      for (int id : dims) {
        char name[NC_MAX_NAME + 1] = {};
        std::size_t length = 0;
        ok(nc_inq_dim(group, id, name, &length));
      }
  }
  int groupAtts = 0;
  if (ok(nc_inq_natts(group, &groupAtts))) walkAttributes(group, NC_GLOBAL, groupAtts);
  int varCount = 0;
  if (ok(nc_inq_varids(group, &varCount, nullptr)) && varCount > 0) {
    std::vector<int> vars(static_cast<std::size_t>(varCount));
    if (ok(nc_inq_varids(group, &varCount, vars.data())))
      for (int v : vars) {
        char name[NC_MAX_NAME + 1] = {};
        nc_type type = NC_NAT;
        int rank = 0;
        int dimIds[NC_MAX_VAR_DIMS] = {};
        int atts = 0;
        // nc_inq_var reads the variable's dimension scales: where libhdf5 looped forever on a
        // corrupt CfRadial-4 file (docs/robustness.md).
        if (!ok(nc_inq_var(group, v, name, &type, &rank, dimIds, &atts))) continue;
        walkAttributes(group, v, atts);
        if (readValues && rank >= 0 && rank <= NC_MAX_VAR_DIMS) walkVariableValues(group, v, type, rank, dimIds);
      }
  }
  int groupCount = 0;
  if (ok(nc_inq_grps(group, &groupCount, nullptr)) && groupCount > 0) {
    std::vector<int> groups(static_cast<std::size_t>(groupCount));
    if (ok(nc_inq_grps(group, &groupCount, groups.data())))
      for (int g : groups) walkGroup(g, readValues, depth + 1);
  }
}

/// The child: never returns.
[[noreturn]] void runChild(const std::string& path, const unsigned char* memory, std::size_t size, bool readValues,
                           double deadlineSeconds, pid_t parent) {
  // Never outlive the parent (it may itself be stopped: a test's bounded case, Ctrl-C), and
  // never run much past the deadline even if nobody is left to enforce it.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(kChildOpenFailed);
  ::alarm(static_cast<unsigned>(deadlineSeconds) + 2);
  ::signal(SIGALRM, SIG_DFL);
  if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
  // A fault is reported by the parent; what the library or a sanitizer prints here is not the
  // user's business (and would land in the middle of the parent's output).
  if (const int devNull = ::open("/dev/null", O_WRONLY); devNull >= 0) {
    ::dup2(devNull, STDOUT_FILENO);
    ::dup2(devNull, STDERR_FILENO);
    if (devNull > STDERR_FILENO) ::close(devNull);
  }
  int ncid = -1;
  const int st = memory ? nc_open_mem(path.c_str(), NC_NOWRITE, size, const_cast<unsigned char*>(memory), &ncid)
                        : nc_open(path.c_str(), NC_NOWRITE, &ncid);
  if (st != NC_NOERR) ::_exit(kChildOpenFailed);
  // Twice: netCDF-C reads attributes lazily and, where that read fails part-way, tries again at
  // the next query; libhdf5 crashed on such a retry (fuzz_odim: a SEGV in H5A__close under
  // nc_inq_attid, after a first failed read). The readers query attributes many times.
  walkGroup(ncid, readValues, 0);
  walkGroup(ncid, false, 0);
  ok(nc_close(ncid));
  ::_exit(gFailedCalls > 0 ? kChildPassedDamaged : kChildPassed);
}

/// Files on disk already checked (the outcome: passed, crashed or timed out), by identity and
/// version (device, inode, size, modification and status-change times, and the mode: a metadata
/// pass says nothing of the values): a reader opens a file twice (format detection, then the
/// read), and a loop re-reads its steps; neither needs a second child. A file rewritten since
/// has other times and is checked again. File times come from the kernel's coarse clock (a few
/// ms): a file rewritten twice within one tick could keep its times, so only a file whose times
/// are over one second old when the check starts is remembered (any later write gets a later
/// time). Bounded: at most 4096 entries (then forgotten and refilled).
using FileIdentity = std::tuple<dev_t, ino_t, off_t, long long, long long, long long, long long, int>;
std::optional<FileIdentity> identityOf(const std::string& path, Hdf5GuardMode mode) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  const long long newest = std::max(st.st_mtim.tv_sec, st.st_ctim.tv_sec);
  if (now.tv_sec - newest < 2) return std::nullopt;  // whole seconds: 2 means over one second
  return FileIdentity{st.st_dev,
                      st.st_ino,
                      st.st_size,
                      static_cast<long long>(st.st_mtim.tv_sec),
                      static_cast<long long>(st.st_mtim.tv_nsec),
                      static_cast<long long>(st.st_ctim.tv_sec),
                      static_cast<long long>(st.st_ctim.tv_nsec),
                      static_cast<int>(mode)};
}
std::mutex& checkedMutex() {
  static std::mutex m;
  return m;
}
std::map<FileIdentity, Hdf5GuardOutcome>& checkedFiles() {
  static std::map<FileIdentity, Hdf5GuardOutcome> s;
  return s;
}

std::string signalName(int sig) {
  const char* abbrev = sigabbrev_np(sig);
  return abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
}

/// A child that waits on a lock: the child is single-threaded (fork copies only the calling
/// thread), so a futex wait there can only be for a lock that another thread of the parent held at
/// the fork and that nobody in the child will ever release. glibc's malloc and stdio take their
/// locks around fork, but an allocator that does not (GCC 12's AddressSanitizer has no fork
/// handler: a CI run's child hung on it until the 30 s deadline while another thread allocated)
/// leaves its lock held in the child. Linux: /proc/PID/syscall names the system call a blocked
/// task is in ("running" when it is not blocked).
}  // namespace

bool processWaitsOnLock(pid_t pid) {
  char file[64];
  std::snprintf(file, sizeof file, "/proc/%d/syscall", static_cast<int>(pid));
  const int fd = ::open(file, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  char text[32] = {};
  const ssize_t n = ::read(fd, text, sizeof text - 1);
  ::close(fd);
  if (n <= 0) return false;
  char* end = nullptr;
  const long number = std::strtol(text, &end, 10);
  return end != text && number == SYS_futex;
}

namespace {

/// Seen waiting on a lock at this many consecutive polls (kLockPollSeconds apart), the child is
/// deadlocked; so many deadlocked children in a row and the check gives up.
constexpr int kLockPolls = 4;
constexpr double kLockPollSeconds = 0.25;
constexpr int kMaxDeadlockedChildren = 3;

struct ChildRun {
  std::string error;  ///< pipe or fork failed
  bool timedOut = false, deadlocked = false;
  int status = 0;  ///< waitpid's status, when neither
};

template <class Elapsed>
ChildRun runChildOnce(const std::string& path, const unsigned char* memory, std::size_t size,
                      const Hdf5GuardSettings& settings, Elapsed elapsed) {
  ChildRun run;
  // The child holds the write end of a pipe until it ends: the parent's poll wakes the moment
  // it exits (or dies), and otherwise every kLockPollSeconds to see whether it waits on a lock.
  int pipeFds[2] = {-1, -1};
  if (::pipe2(pipeFds, O_CLOEXEC) != 0) {
    run.error = std::string("pipe failed: ") + std::strerror(errno);
    return run;
  }
  std::fflush(nullptr);  // the child leaves by _exit, but a buffer copied into it must not be written twice
  const pid_t parent = ::getpid();
  pid_t pid = -1;
  {
    // Forked under the library lock (NetcdfLock.h): no other thread is inside netCDF-C or HDF5, so
    // the child starts from the libraries' state between two calls. The child inherits the lock as
    // held by a thread that does not exist there: it never takes it (runChild calls netCDF-C
    // directly) and never releases it (runChild leaves by _exit, before this scope ends). The
    // parent lets go right after the fork: other threads read on while the child walks the file.
    const NetcdfLock lock;
    pid = ::fork();
    if (pid == 0) {
      ::close(pipeFds[0]);
      runChild(path, memory, size, settings.mode == Hdf5GuardMode::Data, settings.deadlineSeconds, parent);
    }
  }
  if (pid < 0) {
    run.error = std::string("fork failed: ") + std::strerror(errno);
    ::close(pipeFds[0]);
    ::close(pipeFds[1]);
    return run;
  }
  ::close(pipeFds[1]);
  int lockPolls = 0;
  for (;;) {
    const double left = settings.deadlineSeconds - elapsed();
    if (left <= 0.0) {
      run.timedOut = true;
      break;
    }
    pollfd p{pipeFds[0], POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(std::min(left, kLockPollSeconds) * 1000.0 + 1.0));
    if (r > 0) break;  // POLLHUP: the child is gone (it never writes)
    if (r < 0 && errno != EINTR) break;
    if (r == 0) {
      lockPolls = processWaitsOnLock(pid) ? lockPolls + 1 : 0;
      if (lockPolls >= kLockPolls) {
        run.deadlocked = true;
        break;
      }
    }
  }
  ::close(pipeFds[0]);
  if (run.timedOut || run.deadlocked) ::kill(pid, SIGKILL);
  while (::waitpid(pid, &run.status, 0) < 0 && errno == EINTR) {
  }
  return run;
}
}  // namespace

Result<Hdf5GuardSettings> hdf5GuardSettingsFromEnvironment() {
  Hdf5GuardSettings s;
  if (const char* mode = std::getenv("ATMOGLOBE_HDF5_GUARD"); mode && *mode) {
    const std::string m = mode;
    if (m == "metadata") s.mode = Hdf5GuardMode::Metadata;
    else if (m == "data") s.mode = Hdf5GuardMode::Data;
    else if (m == "off") s.mode = Hdf5GuardMode::Off;
    else return makeError("ATMOGLOBE_HDF5_GUARD='" + m + "': expected metadata, data or off");
  }
  if (const char* seconds = std::getenv("ATMOGLOBE_HDF5_GUARD_SECONDS"); seconds && *seconds) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(seconds, &end);
    if (errno != 0 || end == seconds || *end != '\0' || !(v > 0.0) || v > 86400.0)
      return makeError(std::string("ATMOGLOBE_HDF5_GUARD_SECONDS='") + seconds +
                       "': expected a number of seconds in (0, 86400]");
    s.deadlineSeconds = v;
  }
  return s;
}

void forgetHdf5GuardVerdicts() {
  const std::lock_guard lock(checkedMutex());
  checkedFiles().clear();
}

bool looksLikeHdf5(const unsigned char* head, std::size_t size) {
  for (std::size_t at = 0; at + sizeof kSignature <= size; at = at == 0 ? 512 : at * 2)
    if (std::memcmp(head + at, kSignature, sizeof kSignature) == 0) return true;
  return false;
}

Hdf5GuardOutcome checkHdf5InChild(const std::string& path, const unsigned char* memory, std::size_t size,
                                  const Hdf5GuardSettings& settings) {
  Hdf5GuardOutcome out;
  if (settings.mode == Hdf5GuardMode::Off) return out;
  std::optional<FileIdentity> identity;
  if (!memory) {
    identity = identityOf(path, settings.mode);
    const std::lock_guard lock(checkedMutex());
    if (identity)
      if (auto it = checkedFiles().find(*identity); it != checkedFiles().end()) return it->second;
  }
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  int status = 0;
  bool timedOut = false;
  for (int attempt = 1;; ++attempt) {
    const ChildRun run = runChildOnce(path, memory, size, settings, elapsed);
    if (!run.error.empty()) {
      out.message = run.error;
      return out;
    }
    if (run.deadlocked) {
      // Not the file's fault (see waitForChild): another child gets a fresh copy of the locks.
      if (attempt < kMaxDeadlockedChildren) continue;
      out.message = "the check process deadlocked " + std::to_string(attempt) +
                    " times on a lock held by another thread at fork; opening without the check";
      out.seconds = elapsed();
      return out;
    }
    status = run.status;
    timedOut = run.timedOut;
    break;
  }
  out.seconds = elapsed();
  if (timedOut) {
    out.kind = Hdf5GuardOutcome::Kind::TimedOut;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g s", settings.deadlineSeconds);
    out.message = std::string("libhdf5 did not finish reading the file's HDF5 structure within ") + buf +
                  " (ATMOGLOBE_HDF5_GUARD_SECONDS); the file is probably corrupt";
  } else if (WIFEXITED(status) && (WEXITSTATUS(status) == kChildPassed || WEXITSTATUS(status) == kChildPassedDamaged)) {
    out.kind = Hdf5GuardOutcome::Kind::Passed;
    out.damaged = WEXITSTATUS(status) == kChildPassedDamaged;
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == kChildOpenFailed) {
    out.kind = Hdf5GuardOutcome::Kind::OpenFailed;
  } else {
    out.kind = Hdf5GuardOutcome::Kind::Crashed;
    const std::string how = WIFSIGNALED(status) ? "crashed (" + signalName(WTERMSIG(status)) + ")"
                                                : "failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
    out.message = "libhdf5 " + how + " reading the file's HDF5 structure; the file is corrupt";
  }
  if (identity) {
    const std::lock_guard lock(checkedMutex());
    if (checkedFiles().size() >= 4096) checkedFiles().clear();
    checkedFiles()[*identity] = out;
  }
  return out;
}

}  // namespace atmoglobe::io
