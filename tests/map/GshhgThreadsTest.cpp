// GSHHG coastline reads on one thread while two others read a netCDF-4 forecast grid and a
// CfRadial volume: the viewer's case, where the GL thread draws the map (map::GshhgFile) while the
// background loader (engine::ScenePrefetcher) reads the next time steps. netCDF-C is not
// thread-safe; every call of both sides holds the one library lock (io/NetcdfLock.h). Every read
// must give what it gives on one thread, and under ThreadSanitizer (ctest -L threads in
// build-tsan/, scripts/test-sanitized.sh) no race may be reported. The grid and radar opens go
// through the HDF5 guard, which forks under the lock while the other thread waits for it.
//
// ThreadSanitizer cannot see netCDF-C's own global state (the library is not instrumented), so
// the race a missing lock causes there would go unreported. This executable therefore stands in
// for it: it is linked with `ld --wrap` for the netCDF-C calls both sides make (tests/CMakeLists.txt),
// and each wrapper updates one unsynchronised counter, as netCDF-C updates its list of open files,
// before calling the library. Calls that the lock does not order race on that counter, and
// ThreadSanitizer reports it.
#include <atmoglobe/map/Gshhg.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/SyntheticGrid.h>
#include <atmoglobe/volume/SyntheticRadar.h>

#include <gtest/gtest.h>
#include <netcdf.h>

#include <atomic>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

using namespace atmoglobe;

// --- the stand-in for netCDF-C's global state (see the file comment) ---
namespace {
long gNetcdfCalls = 0;  // deliberately not atomic: the library lock must order every update
void netcdfCall() { gNetcdfCalls = gNetcdfCalls + 1; }
}  // namespace

extern "C" {
int __real_nc_open(const char* path, int mode, int* ncid);
int __real_nc_close(int ncid);
int __real_nc_inq_varid(int ncid, const char* name, int* varid);
int __real_nc_get_vara_int(int ncid, int varid, const size_t* start, const size_t* count, int* ip);
int __real_nc_get_vara_short(int ncid, int varid, const size_t* start, const size_t* count, short* sp);
int __real_nc_get_vara_float(int ncid, int varid, const size_t* start, const size_t* count, float* fp);
int __real_nc_get_vara_double(int ncid, int varid, const size_t* start, const size_t* count, double* dp);

int __wrap_nc_open(const char* path, int mode, int* ncid) {
  netcdfCall();
  return __real_nc_open(path, mode, ncid);
}
int __wrap_nc_close(int ncid) {
  netcdfCall();
  return __real_nc_close(ncid);
}
int __wrap_nc_inq_varid(int ncid, const char* name, int* varid) {
  netcdfCall();
  return __real_nc_inq_varid(ncid, name, varid);
}
int __wrap_nc_get_vara_int(int ncid, int varid, const size_t* start, const size_t* count, int* ip) {
  netcdfCall();
  return __real_nc_get_vara_int(ncid, varid, start, count, ip);
}
int __wrap_nc_get_vara_short(int ncid, int varid, const size_t* start, const size_t* count, short* sp) {
  netcdfCall();
  return __real_nc_get_vara_short(ncid, varid, start, count, sp);
}
int __wrap_nc_get_vara_float(int ncid, int varid, const size_t* start, const size_t* count, float* fp) {
  netcdfCall();
  return __real_nc_get_vara_float(ncid, varid, start, count, fp);
}
int __wrap_nc_get_vara_double(int ncid, int varid, const size_t* start, const size_t* count, double* dp) {
  netcdfCall();
  return __real_nc_get_vara_double(ncid, varid, start, count, dp);
}
}

namespace {

/// What a pass over the coastlines and borders of western Europe and the North Atlantic read:
/// lines and points, at two resolutions.
struct CoastSummary {
  std::size_t lines = 0, points = 0;
  double lonSum = 0.0;
  bool operator==(const CoastSummary&) const = default;
};

Result<CoastSummary> readCoasts(const std::string& dir) {
  CoastSummary s;
  for (auto res : {map::GshhgResolution::Crude, map::GshhgResolution::Low})
    for (auto kind : {map::GshhgKind::Shoreline, map::GshhgKind::Border}) {
      auto f = map::GshhgFile::open(map::gshhgPath(dir, kind, res), kind);
      if (!f) return f.forwardError();
      const unsigned levels = kind == map::GshhgKind::Shoreline ? map::kCoastLevels : map::kNationalBorderLevels;
      for (int b : (*f)->binsOverlapping(-40.0, 30.0, 20.0, 70.0)) {
        auto lines = (*f)->readBin(b, levels);
        if (!lines) return lines.forwardError();
        for (const map::GeoPolyline& l : *lines) {
          ++s.lines;
          s.points += l.lonLatDeg.size();
          for (const auto& p : l.lonLatDeg) s.lonSum += p.x;
        }
      }
    }
  return s;
}

/// The finite values of a grid or radar read, summed, and how many there are.
struct ValueSummary {
  std::size_t finite = 0;
  double sum = 0.0;
  bool operator==(const ValueSummary&) const = default;
};

void add(ValueSummary& s, const std::vector<float>& values) {
  for (float v : values)
    if (std::isfinite(v)) ++s.finite, s.sum += v;
}

Result<ValueSummary> readGridAndRadar(const std::string& gridPath, const std::string& radarPath, std::size_t step) {
  ValueSummary s;
  volume::GridReadOptions o;
  o.timeIndex = step;
  o.useGeoid = false;  // no EGM96 file needed
  auto grid = volume::readGridVolume(gridPath, o);
  if (!grid) return grid.forwardError();
  add(s, grid->values);
  auto radar = volume::readRadarVolume(radarPath, {});
  if (!radar) return radar.forwardError();
  for (const volume::Sweep& sw : radar->sweeps) add(s, sw.values);
  return s;
}

}  // namespace

TEST(GshhgThreads, CoastlinesReadWhileWorkersReadGridsAndRadars) {
  const std::string gshhg = map::defaultGshhgDirectory();
  for (auto res : {map::GshhgResolution::Crude, map::GshhgResolution::Low})
    for (auto kind : {map::GshhgKind::Shoreline, map::GshhgKind::Border})
      if (!std::filesystem::exists(map::gshhgPath(gshhg, kind, res)))
        GTEST_SKIP() << map::gshhgPath(gshhg, kind, res) << " missing (apt-get install gmt-gshhg)";

  // Small synthetic files (netCDF-4: the HDF5 guard forks at each open of a file this young).
  const std::string dir = atmoglobe_test::freshTestDir("gshhg_threads");
  const std::string gridPath = dir + "/grid.nc", radarPath = dir + "/radar.nc";
  volume::SyntheticGridOptions g;
  g.nx = 40, g.ny = 40, g.levels = 8, g.times = 3;
  ASSERT_TRUE(volume::writeSyntheticGrid(gridPath, g).ok());
  volume::SyntheticRadarOptions r;
  r.elevationsDeg = {0.5, 1.5, 3.0};
  r.raysPerSweep = 90;
  r.maxRangeMeters = 80000.0;
  ASSERT_TRUE(volume::writeSyntheticCfRadial(radarPath, r).ok());

  // What each side reads on one thread.
  auto coasts = readCoasts(gshhg);
  ASSERT_TRUE(coasts) << coasts.error();
  ASSERT_GT(coasts->points, 1000u);
  std::vector<ValueSummary> steps;
  for (std::size_t t = 0; t < g.times; ++t) {
    auto v = readGridAndRadar(gridPath, radarPath, t);
    ASSERT_TRUE(v) << v.error();
    ASSERT_GT(v->finite, 0u);
    steps.push_back(*v);
  }

  // All at once, many times: two workers loop over the steps as the prefetcher does (and as the GL
  // thread's reloads do beside it), the map side reopens and rereads as a camera move does.
  constexpr int kWorkers = 2, kWorkerReads = 8, kMapReads = 12;
  std::atomic<int> workerErrors{0}, workerMismatches{0};
  std::vector<std::string> firstError(kWorkers);
  std::vector<std::thread> workers;
  for (int w = 0; w < kWorkers; ++w)
    workers.emplace_back([&, w] {
      for (int i = 0; i < kWorkerReads; ++i) {
        const std::size_t t = static_cast<std::size_t>(i + w) % g.times;
        auto v = readGridAndRadar(gridPath, radarPath, t);
        if (!v) {
          if (firstError[static_cast<std::size_t>(w)].empty()) firstError[static_cast<std::size_t>(w)] = v.error();
          ++workerErrors;
        } else if (!(*v == steps[t])) {
          ++workerMismatches;
        }
      }
    });
  int mapMismatches = 0;
  for (int i = 0; i < kMapReads; ++i) {
    auto again = readCoasts(gshhg);
    EXPECT_TRUE(again) << again.error();
    if (again && !(*again == *coasts)) ++mapMismatches;
  }
  for (std::thread& t : workers) t.join();
  EXPECT_EQ(workerErrors.load(), 0) << firstError[0] << firstError[1];
  EXPECT_EQ(workerMismatches.load(), 0);
  EXPECT_EQ(mapMismatches, 0);
}
