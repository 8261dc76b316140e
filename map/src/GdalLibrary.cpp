// GDAL loaded at first use (GdalLibrary.h).
#include "GdalLibrary.h"

#include <dlfcn.h>

#include <cassert>
#include <mutex>
#include <string>

namespace atmoglobe::map::detail {

namespace {
GdalApi api;
bool loaded = false;
}  // namespace

Status loadGdal() {
  static std::once_flag once;
  static std::string error;
  std::call_once(once, [] {
    // The library this program was built against (its soname, from GDAL's CMake package).
    void* library = dlopen(ATMOGLOBE_GDAL_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (!library) {
      const char* why = dlerror();
      error = std::string("GDAL (" ATMOGLOBE_GDAL_LIBRARY ") cannot be loaded") + (why ? std::string(": ") + why : "") +
              "; vector overlays and contours need it (Debian package libgdal32)";
      return;
    }
    GdalApi found;
#define ATMOGLOBE_GDAL_FIND(name)                                                                            \
  found.name = reinterpret_cast<decltype(&::name)>(dlsym(library, #name));                                   \
  if (!found.name) {                                                                                         \
    error = "GDAL (" ATMOGLOBE_GDAL_LIBRARY ") has no function " #name ": not the GDAL this was built with"; \
    return;                                                                                                  \
  }
    ATMOGLOBE_GDAL_FUNCTIONS(ATMOGLOBE_GDAL_FIND)
#undef ATMOGLOBE_GDAL_FIND
    found.GDALAllRegister();
    api = found;
    loaded = true;
  });
  if (!loaded) return makeError(error);
  return Status(Ok{});
}

const GdalApi& gdal() {
  assert(loaded);
  return api;
}

}  // namespace atmoglobe::map::detail
