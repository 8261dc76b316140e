#pragma once
// Bad-input cases run with bounds (docs/robustness.md, "Bad-input suite"): each case runs in a
// forked child with a wall-clock limit (alarm) and a memory cap, so that a crash, a hang or an
// allocation the input cannot back is reported as that case's failure instead of ending the test
// program. Memory: the growth of the child's peak resident set (getrusage ru_maxrss, which starts
// at the parent's resident set at fork) is returned for the test to bound, and outside
// AddressSanitizer the child's address space is capped too (RLIMIT_AS: an allocation beyond the
// cap throws std::bad_alloc, reported as OverMemory). Under ASan the cap is left off (ASan reserves
// terabytes of shadow); ASan itself aborts on allocations over 3 GB, reported as Crashed.
#include <execinfo.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <new>
#include <optional>
#include <string>

namespace atmoglobe_test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kUnderAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kUnderAddressSanitizer = true;
#else
inline constexpr bool kUnderAddressSanitizer = false;
#endif
#else
inline constexpr bool kUnderAddressSanitizer = false;
#endif

struct BoundedOutcome {
  enum class Kind { Read, Error, Crashed, TimedOut, OverMemory };
  Kind kind = Kind::Crashed;
  std::string message;    ///< the reader's error (Error), else what happened
  std::string backtrace;  ///< TimedOut, Crashed: where the child was (backtrace_symbols)
  long rssGrowthKb = 0;   ///< peak resident set growth of the child during the case
  double seconds = 0.0;   ///< wall-clock time of the case
};

inline const char* toString(BoundedOutcome::Kind k) {
  switch (k) {
    case BoundedOutcome::Kind::Read: return "read";
    case BoundedOutcome::Kind::Error: return "error";
    case BoundedOutcome::Kind::Crashed: return "CRASHED";
    case BoundedOutcome::Kind::TimedOut: return "TIMED OUT";
    case BoundedOutcome::Kind::OverMemory: return "OVER THE MEMORY CAP";
  }
  return "?";
}

/// The process's virtual size in bytes (/proc/self/statm, first field in pages).
inline std::size_t virtualBytes() {
  std::ifstream in("/proc/self/statm");
  std::size_t pages = 0;
  in >> pages;
  return pages * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

namespace detail {
inline int backtraceFd = -1;
/// A fatal signal in the child (the alarm, or a crash): writes where it was to the backtrace
/// pipe, then dies of the signal.
inline void onFatalSignal(int sig) {
  void* frames[64];
  const int n = ::backtrace(frames, 64);
  ::backtrace_symbols_fd(frames, n, backtraceFd);
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}
}  // namespace detail

/// Whether a TimedOut or Crashed case stopped inside `library` (e.g. "libhdf5"): in its backtrace,
/// past the signal handler (the frames before the first C-library frame, the signal trampoline),
/// the first frame that is not the C library (raise, abort, another trampoline) or a sanitizer
/// runtime (which reports and aborts from its own handler, and wraps free) is in that library.
/// Third-party hangs and crashes are told apart from ours this way.
inline bool stoppedInside(const BoundedOutcome& o, const std::string& library) {
  auto runtime = [](const std::string& f) {
    return f.find("libc.so") != std::string::npos || f.find("libasan") != std::string::npos ||
           f.find("libubsan") != std::string::npos || f.find("linux-vdso") != std::string::npos;
  };
  bool pastHandler = false;
  std::size_t pos = 0;
  while (pos < o.backtrace.size()) {
    const std::size_t end = std::min(o.backtrace.find('\n', pos), o.backtrace.size());
    const std::string frame = o.backtrace.substr(pos, end - pos);
    pos = end + 1;
    if (!pastHandler) {
      pastHandler = frame.find("libc.so") != std::string::npos;
      continue;
    }
    if (runtime(frame)) continue;
    return frame.find(library) != std::string::npos;
  }
  return false;
}

/// Runs `body` (returns the reader's error, or nullopt when the input was read) in a child
/// process limited to `seconds` of wall time and `capBytes` of new address space.
inline BoundedOutcome runBounded(const std::function<std::optional<std::string>()>& body, unsigned seconds,
                                 std::size_t capBytes) {
  BoundedOutcome out;
  int fds[2], bt[2];
  if (::pipe(fds) != 0 || ::pipe(bt) != 0) {
    out.message = "pipe failed";
    return out;
  }
  std::fflush(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    ::close(bt[0]);
    detail::backtraceFd = bt[1];
    void* warm[1];
    ::backtrace(warm, 1);  // loads libgcc's unwinder now, not inside the signal handler
    // Under AddressSanitizer its own SIGSEGV/SIGBUS handler reports and then aborts (SIGABRT);
    // without it, the crash signals themselves are caught.
    ::signal(SIGALRM, detail::onFatalSignal);
    ::signal(SIGABRT, detail::onFatalSignal);
    if (!kUnderAddressSanitizer)
      for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL}) ::signal(sig, detail::onFatalSignal);
    if (!kUnderAddressSanitizer) {
      const rlim_t limit = static_cast<rlim_t>(virtualBytes() + capBytes);
      const rlimit rl{limit, limit};
      ::setrlimit(RLIMIT_AS, &rl);
    }
    ::alarm(seconds);
    rusage before{}, after{};
    ::getrusage(RUSAGE_SELF, &before);
    char kind = 'X';
    std::string message;
    try {
      const std::optional<std::string> e = body();
      kind = e ? 'E' : 'R';
      message = e.value_or("");
    } catch (const std::bad_alloc&) {
      kind = 'M';
      message = "std::bad_alloc";
    } catch (const std::exception& ex) {
      kind = 'X';
      message = std::string("uncaught exception: ") + ex.what();
    }
    ::getrusage(RUSAGE_SELF, &after);
    const std::string header =
        std::string(1, kind) + std::to_string(after.ru_maxrss - before.ru_maxrss) + "\n" + message;
    std::size_t done = 0;
    while (done < header.size()) {
      const ssize_t n = ::write(fds[1], header.data() + done, header.size() - done);
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  ::close(bt[1]);
  std::string text;
  char buf[4096];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) text.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  for (ssize_t n; (n = ::read(bt[0], buf, sizeof buf)) > 0;) out.backtrace.append(buf, static_cast<std::size_t>(n));
  ::close(bt[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (WIFSIGNALED(status)) {
    out.kind = WTERMSIG(status) == SIGALRM ? BoundedOutcome::Kind::TimedOut : BoundedOutcome::Kind::Crashed;
    out.message = std::string("signal ") + ::strsignal(WTERMSIG(status));
    return out;
  }
  if (text.empty()) {
    out.message = "the child exited (status " + std::to_string(WEXITSTATUS(status)) + ") without a result";
    return out;
  }
  const std::size_t nl = text.find('\n');
  out.rssGrowthKb = std::stol(text.substr(1, nl - 1));
  out.message = text.substr(nl + 1);
  switch (text[0]) {
    case 'R': out.kind = BoundedOutcome::Kind::Read; break;
    case 'E': out.kind = BoundedOutcome::Kind::Error; break;
    case 'M': out.kind = BoundedOutcome::Kind::OverMemory; break;
    default: out.kind = BoundedOutcome::Kind::Crashed; break;
  }
  return out;
}

}  // namespace atmoglobe_test
