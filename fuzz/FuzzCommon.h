// Shared helpers of the fuzz targets (fuzz/README.md). Not a library: included by each target.
#pragma once

#include <atmoglobe/globe/Result.h>

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace atmoglobe::fuzz {

/// The HDF5 guard's deadline (io/Hdf5Guard.h) under the fuzzer: 5 s, well under fuzz/run.sh's
/// -timeout=20, so that a libhdf5 hang is met by the guard (an error) and not reported by
/// libFuzzer as a timeout. A value set by the caller is kept.
[[maybe_unused]] inline const bool kHdf5GuardDeadlineSet = ::setenv("ATMOGLOBE_HDF5_GUARD_SECONDS", "5", 0) == 0;

/// A per-process scratch directory (under $TMPDIR, else /dev/shm, else /tmp) for the readers that
/// only take a path. Removed at exit.
inline const std::filesystem::path& scratchDir() {
  static const std::filesystem::path dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::filesystem::path base = tmp ? tmp : (std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp");
    std::filesystem::path d = base / ("atmoglobe-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    static const std::filesystem::path keep = d;
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(keep, ec);
    });
    return d;
  }();
  return dir;
}

/// Writes the input to scratchDir()/name and returns the path.
inline std::string writeScratch(const std::string& name, const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path p = scratchDir() / name;
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  return p.string();
}

/// The project's rule for bad input: an error that names the input (file or label) and is not
/// empty. A violation aborts, so libFuzzer keeps the input as a finding.
/// `otherName`: a second name that counts (e.g. the scratch directory of the files of a set).
template <typename R>
void checkError(const R& result, const std::string& label, const std::string& otherName = {}) {
  if (result.ok()) return;
  const std::string& e = result.error();
  const bool named = e.find(label) != std::string::npos ||
                     (!otherName.empty() && e.find(otherName) != std::string::npos);
  if (e.empty() || !named) {
    std::fprintf(stderr, "fuzz: error message does not name the input \"%s\": \"%s\"\n", label.c_str(), e.c_str());
    std::abort();
  }
}

}  // namespace atmoglobe::fuzz
