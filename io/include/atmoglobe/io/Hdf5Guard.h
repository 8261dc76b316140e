#pragma once
// The HDF5 guard: a netCDF-4/HDF5 file (CfRadial-2/4, ODIM_H5, netCDF-4 grids) is first opened
// and walked in a forked child process with a deadline, and only a file that the child got
// through is opened in this process.
//
// Why: libhdf5 1.10.8 (Debian 12, under netCDF-C 4.9.0) crashes or loops forever on some
// corrupt files (fuzz_cfradial, fuzz_odim and the bad-input suite: invalid free in
// H5O_msg_reset during nc_open, use-after-free in H5O__msg_iterate_real, an endless loop in
// H5C_protect under nc_inq_var; docs/robustness.md). The fault happens inside the library before
// it returns anything we could check, so the only defence is to let another process meet it
// first. The child opens the file the way the readers do (nc_open / nc_open_mem), visits every
// group, dimension, variable (nc_inq_var, which reads the dimension scales) and attribute, and
// with `Hdf5GuardMode::Data` also reads every variable's values; then it exits. A child killed by
// a signal, one that exits with an error status (a sanitizer report), or one that runs past the
// deadline makes the open fail with a message naming the file and what happened; the parent never
// touched the file.
//
// Cost: one fork and one extra metadata walk per HDF5 open (measured in docs/robustness.md,
// "The HDF5 guard"). Classic netCDF files do not go through it: their header is walked by our own
// code first (NetcdfFile.cpp, classicHeaderProblem).
//
// Threads: fork() copies only the calling thread. The child uses netCDF-C/HDF5 only, and every
// call into them in the process holds netcdfLibraryMutex() (NetcdfLock.h); the fork holds it too,
// so the child never sees another thread half-way through them. The child never takes that lock
// (its copy is held by a thread that does not exist in the child); the parent releases it right
// after the fork, so other threads read on while the child walks the file. The child's
// stdout/stderr go to /dev/null and it leaves by _exit (no atexit handlers, no flushing of the
// parent's buffers). Another thread may still hold a lock the child needs (an allocator without a
// fork handler: GCC 12's AddressSanitizer); the child then waits forever. The parent watches for
// that (processWaitsOnLock, every 0.25 s): a child seen waiting on a lock for 1 s is killed and the
// check forked again, up to 3 times; after that the file is opened without the check, as when
// fork fails.
//
// Settings (environment, read once per call):
//   ATMOGLOBE_HDF5_GUARD=metadata (default) | data | off
//   ATMOGLOBE_HDF5_GUARD_SECONDS=S   the child's deadline (default 30 s; a metadata walk of the
//                                    largest sample file takes well under a second)
#include <atmoglobe/globe/Result.h>

#include <sys/types.h>

#include <cstddef>
#include <string>

namespace atmoglobe::io {

enum class Hdf5GuardMode {
  Off,       ///< open HDF5 files in this process directly
  Metadata,  ///< the child walks groups, dimensions, variables and attributes
  Data,      ///< ... and reads every variable's values too
};

struct Hdf5GuardSettings {
  Hdf5GuardMode mode = Hdf5GuardMode::Metadata;
  double deadlineSeconds = 30.0;
};

/// The settings from ATMOGLOBE_HDF5_GUARD / ATMOGLOBE_HDF5_GUARD_SECONDS; an unknown value is an
/// error naming the variable.
Result<Hdf5GuardSettings> hdf5GuardSettingsFromEnvironment();

/// True when `head` (the first bytes of a file) holds the HDF5 signature at offset 0, 512, 1024,
/// 2048, ... (HDF5 allows a user block before the superblock).
bool looksLikeHdf5(const unsigned char* head, std::size_t size);

/// What the child found. `Passed`: it opened and walked the file. `OpenFailed`: netCDF-C refused
/// the file cleanly in the child (the caller's own open gives the proper message). Otherwise
/// `message` says what happened ("libhdf5 crashed (SIGSEGV) ...").
struct Hdf5GuardOutcome {
  enum class Kind { Passed, OpenFailed, Crashed, TimedOut, NotRun };
  Kind kind = Kind::NotRun;
  /// Passed, but some library calls of the walk failed (the file is damaged): the caller then
  /// leaves libhdf5's identifiers alone (NetcdfFile's leaked-attribute clean-up, which crashed
  /// libhdf5 later in a fuzzing process after such files).
  bool damaged = false;
  std::string message;   ///< for Crashed / TimedOut / NotRun
  double seconds = 0.0;  ///< wall-clock time of the check
};

/// Runs the check of a file on disk (`memory` null) or of a file image in memory (nc_open_mem;
/// `path` is then the label netCDF-C is given). NotRun: the mode is Off, fork() failed, or three
/// children in a row deadlocked (the message says why; the caller then opens in process).
Hdf5GuardOutcome checkHdf5InChild(const std::string& path, const unsigned char* memory, std::size_t size,
                                  const Hdf5GuardSettings& settings);

/// True when the process `pid` is blocked in a futex wait (Linux: /proc/PID/syscall). In the
/// guard's single-threaded child that means a lock held at the fork by a thread that does not
/// exist there: it is never released.
bool processWaitsOnLock(pid_t pid);

/// Forgets the remembered verdicts (benches measuring the first open of a file; tests).
void forgetHdf5GuardVerdicts();

}  // namespace atmoglobe::io
