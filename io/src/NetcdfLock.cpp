#include <atmoglobe/io/NetcdfLock.h>

namespace atmoglobe::io {

std::recursive_mutex& netcdfLibraryMutex() {
  static std::recursive_mutex m;
  return m;
}

}  // namespace atmoglobe::io
