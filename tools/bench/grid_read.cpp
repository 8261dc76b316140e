// bench_grid_read: what a forecast-grid read costs, whole and cropped.
//
//   bench_grid_read [--runs N] [--big] [DATA_DIR]   (--help: the options)
//
// Files: the default SYNTHETIC grid (400 x 400 x 35 x 13 shorts, deflated in chunks of
// 1 x 7 x 100 x 100), written to a temporary directory; with --big also a SYNTHETIC grid of
// 1000 x 1000 x 50 x 13 shorts stored uncompressed (1.3 GB on disk: the "big file" case, removed
// afterwards); and the real WRF and ECHAM5 files under DATA_DIR/grids when present.
// Cases per file: describeGridFile; one whole time step of the default variable; a crop (a
// 1 x 1 degree box at the grid's centre, the lowest 10 levels, one step).
// Columns: median wall time over N runs (page cache warm: every run after the first reads from
// memory, so the time is the reader's, not the disk's), the reader's bytesRead (variable data
// asked for, in stored size), and the bytes that crossed read(2) ("rchar" of /proc/self/io,
// HDF5 chunk reads included) in the last run. Prints a Markdown table (docs/grids.md).
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/SyntheticGrid.h>

#include "BenchCli.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

using namespace atmoglobe;
using namespace atmoglobe::volume;
using Clock = std::chrono::steady_clock;

namespace {

/// Bytes this process has passed through read(2)-like calls so far (/proc/self/io "rchar").
std::uint64_t rchar() {
  std::ifstream in("/proc/self/io");
  std::string key;
  std::uint64_t value = 0;
  while (in >> key >> value)
    if (key == "rchar:") return value;
  return 0;
}

struct Measure {
  double seconds = -1;
  std::uint64_t bytesRead = 0, rcharBytes = 0;
  std::string error;
};

Measure measure(int runs, const std::function<Result<std::uint64_t>()>& f) {
  Measure m;
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    const std::uint64_t r0 = rchar();
    const auto t0 = Clock::now();
    auto r = f();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    if (!r) {
      m.error = r.error();
      return m;
    }
    m.bytesRead = *r;
    m.rcharBytes = rchar() - r0;
  }
  std::sort(t.begin(), t.end());
  m.seconds = t[t.size() / 2];
  return m;
}

std::string mb(std::uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, bytes >= 100000 ? "%.1f MB" : "%.3f MB", static_cast<double>(bytes) / 1e6);
  return buf;
}

void benchFile(const std::string& label, const std::string& path, int runs) {
  auto info = describeGridFile(path);
  if (!info) {
    std::printf("| %s | (%s) | | | | |\n", label.c_str(), info.error().c_str());
    return;
  }
  std::uint64_t varBytes = 0;
  for (const auto& v : info->variables)
    if (v.name == info->variable) {
      varBytes = v.type == "short" ? 2 : v.type == "double" ? 8 : v.type == "byte" ? 1 : 4;
      for (std::size_t d : v.shape) varBytes *= d;
    }
  const double midLat = 0.5 * (info->southDeg + info->northDeg), midLon = 0.5 * (info->westDeg + info->eastDeg);
  struct Case {
    std::string name;
    std::function<Result<std::uint64_t>()> run;
  };
  GridReadOptions step;
  GridReadOptions crop;
  crop.crop.southDeg = midLat - 0.5;
  crop.crop.northDeg = midLat + 0.5;
  crop.crop.westDeg = midLon - 0.5;
  crop.crop.eastDeg = midLon + 0.5;
  crop.crop.levelCount = 10;
  std::size_t cropColumns = 0;
  const std::vector<Case> cases = {
      {"describe",
       [&]() -> Result<std::uint64_t> {
         auto r = describeGridFile(path);
         if (!r) return r.forwardError();
         return r->bytesRead;
       }},
      {"one step, whole grid",
       [&]() -> Result<std::uint64_t> {
         auto r = readGridVolume(path, step);
         if (!r) return r.forwardError();
         return r->bytesRead;
       }},
      {"one step, 1 x 1 deg, 10 levels",
       [&]() -> Result<std::uint64_t> {
         auto r = readGridVolume(path, crop);
         if (!r) return r.forwardError();
         cropColumns = r->nx * r->ny;
         return r->bytesRead;
       }},
  };
  for (const Case& c : cases) {
    const Measure m = measure(runs, c.run);
    if (!m.error.empty()) {
      std::printf("| %s | %s | error: %s | | | |\n", label.c_str(), c.name.c_str(), m.error.c_str());
      continue;
    }
    std::string name = c.name;
    if (name.find("1 x 1") != std::string::npos) name += " (" + std::to_string(cropColumns) + " columns)";
    std::printf("| %s (%s variable `%s`) | %s | %.1f ms | %s | %s | %.2f %% |\n", label.c_str(), mb(varBytes).c_str(),
                info->variable.c_str(), name.c_str(), m.seconds * 1e3, mb(m.bytesRead).c_str(),
                mb(m.rcharBytes).c_str(),
                varBytes ? 100.0 * static_cast<double>(m.bytesRead) / static_cast<double>(varBytes) : 0.0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5;
  bool big = false;
  std::string data = ATMOGLOBE_SHARED_DATA_DIR;
  CLI::App app{"Benchmark: what a forecast-grid read costs, whole and cropped (a Markdown table, docs/grids.md)",
               "bench_grid_read"};
  app.add_option("--runs", runs, "Timed runs per case (median; default 5)")->check(benchcli::numberIn(1));
  app.add_flag("--big", big,
               "Also a 1000 x 1000 x 50 x 13 uncompressed SYNTHETIC grid (1.3 GB on disk, removed after)");
  app.add_option(
      "DATA_DIR", data,
      "Directory holding grids/ with the real WRF and ECHAM5 files (default: ../shared/data beside the source tree)");
  if (const int rc = benchcli::parse(app, argc, argv); rc >= 0) return rc;
  const std::filesystem::path tmp =
      std::filesystem::temp_directory_path() / ("bench_grid_read." + std::to_string(getpid()));
  std::filesystem::create_directories(tmp);
  std::printf(
      "| file | case | median time | bytesRead | read(2) bytes | bytesRead / variable |\n|---|---|---|---|---|---|\n");
  {
    const std::string path = (tmp / "synthetic_default.nc").string();
    const auto t0 = Clock::now();
    if (auto st = writeSyntheticGrid(path, SyntheticGridOptions{}); !st) {
      std::fprintf(stderr, "%s\n", st.error().c_str());
      return 1;
    }
    std::fprintf(stderr, "wrote the default synthetic grid in %.2f s, %.1f MB\n",
                 std::chrono::duration<double>(Clock::now() - t0).count(),
                 static_cast<double>(std::filesystem::file_size(path)) / 1e6);
    benchFile("synthetic default, deflated", path, runs);
  }
  if (big) {
    const std::string path = (tmp / "synthetic_big.nc").string();
    SyntheticGridOptions o;
    o.nx = 1000;
    o.ny = 1000;
    o.levels = 50;
    o.spacingKm = 2.0;
    o.deflateLevel = 0;  // contiguous, uncompressed: the file is as large as its data
    const auto t0 = Clock::now();
    if (auto st = writeSyntheticGrid(path, o); !st) {
      std::fprintf(stderr, "%s\n", st.error().c_str());
      return 1;
    }
    std::fprintf(stderr, "wrote the big synthetic grid in %.1f s, %.2f GB\n",
                 std::chrono::duration<double>(Clock::now() - t0).count(),
                 static_cast<double>(std::filesystem::file_size(path)) / 1e9);
    benchFile("synthetic 1000 x 1000 x 50 x 13, uncompressed", path, runs);
    std::filesystem::remove(path);
  }
  for (const char* f : {"grids/wrf_python_ci_test_file.nc", "grids/rectilinear_grid_3D.nc"}) {
    const std::string path = data + "/" + f;
    if (std::filesystem::exists(path)) benchFile(f, path, runs);
  }
  std::filesystem::remove_all(tmp);
  return 0;
}
