// bench_radar_read_geolocate: radar read time against the I/O floor, and gate geolocation speed.
//
//   bench_radar_read_geolocate [--runs N] [--read-only] [--guard-only] [DATA_DIR]   (--help: the options)
//
// --runs N: at least 5 (default 7). --read-only: parts 1 and 3 only (no geolocation). --guard-only:
// part 3 only. DATA_DIR: default ../shared/data (beside the checkout).
//
// 1. For every radar file under DATA_DIR/radar_{nexrad,odim,cfradial}: median wall time of
//    readRadarVolume (default field, values decoded) over N runs, next to the "floor": the same
//    bytes read with plain library calls and nothing else (NEXRAD: read the file + libbz2
//    BZ2_bzBuffToBuffDecompress of every record; netCDF/HDF5: nc_open + nc_get_var of the loaded
//    field's variables in their stored type, each into its own buffer held to the end as the
//    reader holds every sweep + nc_close). Read and floor runs alternate.
// 2. Gate geolocation over every gate of the NEXRAD REF volume: gates per second for the exact
//    path (geolocateGateExact) and the fast path (geolocateSweepFast), and the fast path's maximum
//    ECEF distance from the exact result.
// 3. The HDF5 guard's cost (io/Hdf5Guard.h): for every netCDF-4/HDF5 radar file, the median
//    wall time of a first readRadarVolume with the guard off, walking metadata (the default) and
//    reading every value in the child; the three runs alternate and the guard's remembered
//    verdicts are forgotten before each, so every run pays what a first open pays.
// Prints Markdown tables (docs/bench-radar.md holds a copy and the command).
#include <atmoglobe/io/Hdf5Guard.h>
#include <atmoglobe/io/NetcdfLock.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/RadarReader.h>

#include "BenchCli.h"

#include <bzlib.h>
#include <dlfcn.h>
#include <netcdf.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <tuple>
#include <vector>

using namespace atmoglobe;
using Clock = std::chrono::steady_clock;

namespace {

double medianSeconds(int runs, const std::function<bool()>& f) {
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = Clock::now();
    if (!f()) return -1.0;
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

// Minor page faults of this process so far (first touches of fresh pages).
long minorFaults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

struct PairTiming {
  double aSeconds = -1.0, bSeconds = -1.0;  // medians; -1 if a run failed
  long aFaults = 0, bFaults = 0;            // minor page faults per run (mean)
};

// Medians of a and b over `runs` alternating runs each (a, b, a, b ...).
// `afterB` runs after each run of b, outside the timing.
PairTiming medianSecondsPair(int runs, const std::function<bool()>& a, const std::function<bool()>& b,
                             const std::function<void()>& afterB) {
  std::vector<double> ta, tb;
  long fa = 0, fb = 0;
  for (int i = 0; i < runs; ++i) {
    for (auto [f, t, faults] : {std::tuple{&a, &ta, &fa}, std::tuple{&b, &tb, &fb}}) {
      const long f0 = minorFaults();
      const auto t0 = Clock::now();
      if (!(*f)()) return {};
      t->push_back(std::chrono::duration<double>(Clock::now() - t0).count());
      *faults += minorFaults() - f0;
    }
    if (afterB) afterB();
  }
  std::sort(ta.begin(), ta.end());
  std::sort(tb.begin(), tb.end());
  return {ta[ta.size() / 2], tb[tb.size() / 2], fa / runs, fb / runs};
}

// Floor for NEXRAD: read the file, decompress every record with the one-shot libbz2 call.
bool nexradFloor(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> file{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  static std::vector<char> out(16 << 20);
  std::size_t pos = 24;
  while (pos + 4 <= file.size()) {
    const auto* p = reinterpret_cast<const unsigned char*>(&file[pos]);
    const auto control = static_cast<std::int32_t>((std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) |
                                                   (std::uint32_t{p[2]} << 8) | p[3]);
    const std::size_t len = static_cast<std::size_t>(control < 0 ? -static_cast<std::int64_t>(control) : control);
    pos += 4;
    if (len > file.size() - pos) return false;
    unsigned outLen = static_cast<unsigned>(out.size());
    if (BZ2_bzBuffToBuffDecompress(out.data(), &outLen, &file[pos], static_cast<unsigned>(len), 0, 0) != BZ_OK)
      return false;
    pos += len;
    if (control < 0) break;
  }
  return true;
}

bool readVar(int ncid, int varid, std::vector<char>* buf) {
  int ndims = 0;
  nc_type type;
  int dims[NC_MAX_VAR_DIMS];
  if (nc_inq_var(ncid, varid, nullptr, &type, &ndims, dims, nullptr) != NC_NOERR) return false;
  std::size_t count = 1, len = 0;
  for (int d = 0; d < ndims; ++d) {
    if (nc_inq_dimlen(ncid, dims[d], &len) != NC_NOERR) return false;
    count *= len;
  }
  std::size_t typeSize = 0;
  if (nc_inq_type(ncid, type, nullptr, &typeSize) != NC_NOERR) return false;
  buf->resize(count * typeSize);
  return nc_get_var(ncid, varid, buf->data()) == NC_NOERR;
}

std::string textAttribute(int ncid, int varid, const char* name) {
  std::size_t len = 0;
  if (nc_inq_attlen(ncid, varid, name, &len) != NC_NOERR || len > 4096) return {};
  nc_type type;
  if (nc_inq_atttype(ncid, varid, name, &type) != NC_NOERR) return {};
  if (type == NC_CHAR) {
    std::string s(len, '\0');
    if (nc_get_att_text(ncid, varid, name, s.data()) != NC_NOERR) return {};
    while (!s.empty() && s.back() == '\0') s.pop_back();
    return s;
  }
  if (type == NC_STRING) {
    std::vector<char*> v(len);
    if (nc_get_att_string(ncid, varid, name, v.data()) != NC_NOERR || len == 0) return {};
    std::string s = v[0] ? v[0] : "";
    nc_free_string(len, v.data());
    return s;
  }
  return {};
}

// netCDF-C 4.9.0 over HDF5 1.10.8 leaves one HDF5 attribute id open per ODIM data array on every
// nc_open, and HDF5 scans all open attribute ids on each attribute open, so leaked ids slow down
// every later attribute read in the process. The reader closes the ones of its own file
// (NetcdfFile); after each floor run, outside its timing, this closes the ones the floor's plain
// netCDF-C calls left, so that neither side's runs inherit the other's leak. Safe here: nothing
// else in this process holds an HDF5 attribute open between runs.
void closeLeakedHdf5Attributes() {
  const io::NetcdfLock lock;   // direct HDF5 calls (io/NetcdfLock.h)
  using hid_t = std::int64_t;  // HDF5 >= 1.10
  static auto count = reinterpret_cast<long (*)(hid_t, unsigned)>(dlsym(RTLD_DEFAULT, "H5Fget_obj_count"));
  static auto ids =
      reinterpret_cast<long (*)(hid_t, unsigned, std::size_t, hid_t*)>(dlsym(RTLD_DEFAULT, "H5Fget_obj_ids"));
  static auto close = reinterpret_cast<int (*)(hid_t)>(dlsym(RTLD_DEFAULT, "H5Aclose"));
  if (!count || !ids || !close) return;
  constexpr hid_t kAllFiles = 0x001F;  // H5F_OBJ_ALL
  constexpr unsigned kAttr = 0x0010u;  // H5F_OBJ_ATTR
  const long n = count(kAllFiles, kAttr);
  if (n <= 0) return;
  std::vector<hid_t> open(static_cast<std::size_t>(n));
  const long got = ids(kAllFiles, kAttr, open.size(), open.data());
  for (long i = 0; i < got && i < n; ++i) close(open[static_cast<std::size_t>(i)]);
}

// Floor for netCDF/HDF5: open, read the loaded field's arrays raw, close.
bool netcdfFloor(const std::string& path, const std::string& field, bool odim) {
  const io::NetcdfLock lock;  // direct netCDF-C calls (io/NetcdfLock.h)
  int ncid = 0;
  if (nc_open(path.c_str(), NC_NOWRITE, &ncid) != NC_NOERR) return false;
  // Every array read is kept until the end, as the reader keeps every sweep.
  std::vector<std::vector<char>> arrays;
  bool ok = true;
  if (!odim) {
    int varid = 0;
    ok = nc_inq_varid(ncid, field.c_str(), &varid) == NC_NOERR && readVar(ncid, varid, &arrays.emplace_back());
  } else {
    for (int n = 1; ok; ++n) {
      int ds = 0;
      if (nc_inq_grp_ncid(ncid, ("dataset" + std::to_string(n)).c_str(), &ds) != NC_NOERR) break;
      for (int m = 1;; ++m) {
        int data = 0, what = 0, varid = 0;
        if (nc_inq_grp_ncid(ds, ("data" + std::to_string(m)).c_str(), &data) != NC_NOERR) break;
        if (nc_inq_grp_ncid(data, "what", &what) != NC_NOERR) continue;
        if (textAttribute(what, NC_GLOBAL, "quantity") != field) continue;
        ok = nc_inq_varid(data, "data", &varid) == NC_NOERR && readVar(data, varid, &arrays.emplace_back());
        break;
      }
    }
  }
  nc_close(ncid);
  return ok;
}

// Median read and floor times for every radar file. The read and floor runs alternate
// (read, floor, read, floor ...) so that a change in machine load hits both alike. Each file is
// measured in its own child process (fork), so that what one file's runs leave behind (heap
// growth and malloc's raised mmap threshold after NEXRAD, library state) does not change the
// next file's figures; until 2026-11-22 one process measured every file in turn.
void readTable(const std::string& dataDir, int runs) {
  std::printf("## Read time (median of %d runs, read and floor alternating)\n\n", runs);
  std::printf(
      "| file | format | field | read (ms) | floor (ms) | read / floor | page faults per read / floor |\n"
      "|---|---|---|---|---|---|---|\n");
  for (const char* sub : {"radar_nexrad", "radar_odim", "radar_cfradial"}) {
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(dataDir) / sub, ec))
      files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      std::fflush(stdout);
      const pid_t child = fork();
      if (child > 0) {
        int status = 0;
        waitpid(child, &status, 0);
        continue;
      }
      if (child < 0) std::perror("fork (measuring in this process)");
      const std::string path = f.string();
      std::string format, field;
      {
        // The probe's volume is not held during the timed runs.
        Result<volume::RadarVolume> probe = volume::readRadarVolume(path, {});
        if (!probe) {
          std::printf("| %s | error: %s | | | | | |\n", f.filename().c_str(), probe.error().c_str());
          if (child == 0) {
            std::fflush(stdout);
            _exit(0);
          }
          continue;
        }
        format = probe->format;
        field = probe->loadedField.name;
      }
      std::function<bool()> floorFn;
      if (format == "NEXRAD Level II") {
        floorFn = [&] { return nexradFloor(path); };
      } else {
        const bool odim = format.rfind("ODIM", 0) == 0;
        floorFn = [&, odim] { return netcdfFloor(path, field, odim); };
      }
      const PairTiming t = medianSecondsPair(
          runs, [&] { return volume::readRadarVolume(path, {}).ok(); }, floorFn, closeLeakedHdf5Attributes);
      std::printf("| %s | %s | %s | %.1f | %.1f | %.2f | %ld / %ld |\n", f.filename().c_str(), format.c_str(),
                  field.c_str(), t.aSeconds * 1e3, t.bSeconds * 1e3, t.bSeconds > 0 ? t.aSeconds / t.bSeconds : 0.0,
                  t.aFaults, t.bFaults);
      if (child == 0) {
        std::fflush(stdout);
        _exit(0);
      }
    }
  }
  std::printf("\n");
}

// Part 3: the HDF5 guard's cost per first open, three modes alternating.
void guardTable(const std::string& dataDir, int runs) {
  std::printf("## HDF5 guard cost (median of %d first reads per mode, modes alternating)\n\n", runs);
  std::printf(
      "| file | size (MB) | guard off (ms) | metadata, the default (ms) | ratio | data (ms) | ratio |\n"
      "|---|---|---|---|---|---|---|\n");
  const char* modes[3] = {"off", "metadata", "data"};
  for (const char* sub : {"radar_odim", "radar_cfradial"}) {
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& e : std::filesystem::recursive_directory_iterator(std::filesystem::path(dataDir) / sub, ec))
      if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      const std::string path = f.string();
      unsigned char head[8] = {};
      std::ifstream in(path, std::ios::binary);
      in.read(reinterpret_cast<char*>(head), sizeof head);
      if (!io::looksLikeHdf5(head, static_cast<std::size_t>(in.gcount()))) continue;
      std::vector<double> t[3];
      bool ok = true;
      for (int i = 0; i < runs && ok; ++i)
        for (int m = 0; m < 3 && ok; ++m) {
          ::setenv("ATMOGLOBE_HDF5_GUARD", modes[m], 1);
          io::forgetHdf5GuardVerdicts();
          const auto t0 = Clock::now();
          ok = volume::readRadarVolume(path, {}).ok();
          t[m].push_back(std::chrono::duration<double>(Clock::now() - t0).count());
          closeLeakedHdf5Attributes();
        }
      ::unsetenv("ATMOGLOBE_HDF5_GUARD");
      if (!ok) {
        std::printf("| %s | read failed | | | | | |\n", f.filename().c_str());
        continue;
      }
      double med[3];
      for (int m = 0; m < 3; ++m) {
        std::sort(t[m].begin(), t[m].end());
        med[m] = t[m][t[m].size() / 2];
      }
      std::printf("| %s | %.2f | %.1f | %.1f | %.2f | %.1f | %.2f |\n", f.filename().c_str(),
                  static_cast<double>(std::filesystem::file_size(f)) / 1e6, med[0] * 1e3, med[1] * 1e3, med[1] / med[0],
                  med[2] * 1e3, med[2] / med[0]);
      std::fflush(stdout);
    }
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 7;
  bool readOnly = false;
  bool guardOnly = false;
  std::string dataDir = ATMOGLOBE_SHARED_DATA_DIR;
  CLI::App app{
      "Benchmark: radar read time against the I/O floor, the HDF5 guard's cost, and gate geolocation "
      "speed (Markdown tables, docs/bench-radar.md)",
      "bench_radar_read_geolocate"};
  app.add_option("--runs", runs, "Timed runs per file and case (median; at least 5, default 7)")
      ->check(benchcli::numberIn(5));
  app.add_flag("--read-only", readOnly, "The read and guard tables only (no geolocation)");
  app.add_flag("--guard-only", guardOnly, "The HDF5 guard's table only");
  app.add_option(
      "DATA_DIR", dataDir,
      "Directory holding radar_nexrad/, radar_odim/, radar_cfradial/ (default: ../shared/data beside the source tree)");
  if (const int rc = benchcli::parse(app, argc, argv); rc >= 0) return rc;
  if (!guardOnly) readTable(dataDir, runs);
  guardTable(dataDir, runs);
  if (guardOnly) return 0;

  if (readOnly) return 0;

  // Geolocation over the NEXRAD REF volume.
  const std::string nexrad = dataDir + "/radar_nexrad/KLBB20160601_150025_V06";
  Result<volume::LoadedRadar> loaded = volume::loadRadar(nexrad, {});
  if (!loaded) {
    std::fprintf(stderr, "%s\n", loaded.error().c_str());
    return 1;
  }
  const volume::RadarVolume* vol = &loaded->volume;
  const volume::SiteResolution* site = &loaded->site;
  const volume::BeamModel model;
  std::size_t gates = 0;
  double maxRange = 0;
  for (const volume::Sweep& s : vol->sweeps) {
    gates += s.rayCount() * s.gateCount;
    maxRange = std::max(maxRange, s.gateRangeMeters(s.gateCount - 1));
  }
  std::vector<std::vector<glm::dvec3>> exact(vol->sweeps.size()), fast(vol->sweeps.size());
  const double exactSeconds = medianSeconds(3, [&] {
    for (std::size_t k = 0; k < vol->sweeps.size(); ++k) {
      const volume::Sweep& s = vol->sweeps[k];
      exact[k].resize(s.rayCount() * s.gateCount);
      for (std::size_t i = 0; i < s.rayCount(); ++i)
        for (std::uint32_t g = 0; g < s.gateCount; ++g)
          exact[k][i * s.gateCount + g] =
              volume::geolocateGateExact(site->site, model, s.azimuthDeg[i], s.elevationDeg[i], s.gateRangeMeters(g))
                  .ecef;
    }
    return true;
  });
  const double fastSeconds = medianSeconds(runs, [&] {
    for (std::size_t k = 0; k < vol->sweeps.size(); ++k)
      volume::geolocateSweepFast(site->site, model, vol->sweeps[k], &fast[k]);
    return true;
  });
  double maxError = 0;
  for (std::size_t k = 0; k < vol->sweeps.size(); ++k)
    for (std::size_t j = 0; j < exact[k].size(); ++j)
      maxError = std::max(maxError, glm::length(fast[k][j] - exact[k][j]));
  std::printf("\n## Gate geolocation (KLBB REF volume: %zu gates, ranges to %.1f km, ke 4/3, WGS84 site radius)\n\n",
              gates, maxRange / 1e3);
  std::printf("| path | time (ms) | gates/s | speed-up | max error vs exact |\n|---|---|---|---|---|\n");
  std::printf("| exact (median of 3) | %.1f | %.3g | 1.0 | 0 (reference) |\n", exactSeconds * 1e3,
              static_cast<double>(gates) / exactSeconds);
  std::printf("| fast (median of %d) | %.1f | %.3g | %.1f | %.3g m |\n", runs, fastSeconds * 1e3,
              static_cast<double>(gates) / fastSeconds, exactSeconds / fastSeconds, maxError);
  return 0;
}
