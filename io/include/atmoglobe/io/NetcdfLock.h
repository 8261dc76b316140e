#pragma once
// The one process-wide lock around netCDF-C and HDF5.
//
// netCDF-C is not thread-safe: its list of open files and its netCDF-4 layer's state are globals
// without locks (Debian 12's libhdf5 is built thread-safe, but that serialises only libhdf5's own
// calls, not netCDF-C's use of them). Yet the viewer reads on two threads: its background loader
// (engine/SceneTime.h, ScenePrefetcher) reads grids and radar volumes while the GL thread reads
// coastlines (map/Gshhg.h) and reloads what the panel changed. So every netCDF-C or HDF5 call in
// the process is made while holding this lock:
//
//   Each public entry point that reaches netCDF-C or HDF5 takes it: io's NetcdfFile members and
//   HDF5 guard, volume's grid reader and netCDF writers, map's GSHHG and vector-file readers, the
//   benches' direct reads. A caller may hold it across several such calls. It is recursive, so an
//   entry point that calls another one under it does not deadlock.
//
// It is held per call into the libraries (NetcdfFile's members, the grid reader's own direct
// calls), not per file read: a reader's decoding, cropping and the rest run outside it, so the
// GL thread's coastline read waits for one library call of the loader at most.
//
// The HDF5 guard (Hdf5Guard.h) forks while holding it, so that no other thread is half-way
// through the libraries at the fork; the child never takes it (its copy is owned by a thread
// that does not exist there) and calls netCDF-C directly.
#include <mutex>

namespace atmoglobe::io {

/// The lock itself (a function-local static: ready before any other static needs it).
std::recursive_mutex& netcdfLibraryMutex();

/// Turns off HDF5's printing of its error stack on the calling thread (once per thread). HDF5
/// keeps that setting per thread; netCDF-C turns it off only on the thread that first opens a
/// file, so a worker thread's open printed pages of "HDF5-DIAG: Error detected" for attributes
/// netCDF-C merely probes for. Our errors come from netCDF-C's return codes.
void quietHdf5ErrorStackOnThisThread();

/// Holds netcdfLibraryMutex() for its lifetime: `const io::NetcdfLock lock;`. Also quiets HDF5's
/// error printing on the thread (quietHdf5ErrorStackOnThisThread).
class NetcdfLock {
 public:
  [[nodiscard]] NetcdfLock() : lock_(netcdfLibraryMutex()) { quietHdf5ErrorStackOnThisThread(); }
  NetcdfLock(const NetcdfLock&) = delete;
  NetcdfLock& operator=(const NetcdfLock&) = delete;

 private:
  std::lock_guard<std::recursive_mutex> lock_;
};

}  // namespace atmoglobe::io
