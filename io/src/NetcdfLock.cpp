#include <atmoglobe/io/NetcdfLock.h>

#include <hdf5.h>

namespace atmoglobe::io {

std::recursive_mutex& netcdfLibraryMutex() {
  static std::recursive_mutex m;
  return m;
}

void quietHdf5ErrorStackOnThisThread() {
  thread_local bool quiet = false;
  if (quiet) return;
  quiet = true;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

}  // namespace atmoglobe::io
