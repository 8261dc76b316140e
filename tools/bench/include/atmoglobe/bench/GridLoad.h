#pragma once
// The grid bench's load measurements: what reading a view's crop costs against the I/O floor
// (plain netCDF-C nc_get_vara of the same hyperslabs: the variable and what its heights come
// from) and against the whole variable. Each case runs in a fresh child process (the bench's own
// executable with `--load-probe JOB RESULT`, no shell) so that its peak memory (VmHWM) is its
// own: a case in the parent would inherit the pages and the malloc arenas of the cases before.
#include <atmoglobe/bench/Views.h>
#include <atmoglobe/globe/Result.h>

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace atmoglobe::bench {

/// One hyperslab of one variable: start and count per dimension (file order).
struct Hyperslab {
  std::string variable;
  std::vector<std::size_t> start, count;
};

/// The hyperslabs readGridVolume reads for `crop` (a crop across a global grid's seam: two per
/// variable): the variable's and those of `heightVariables` (3-D ones on the same levels; 2-D
/// ones, e.g. a surface altitude, on the same rows and columns). `cropped` is what readGridVolume
/// returned for it (its file indices say where the crop lies). Errors name the file.
Result<std::vector<Hyperslab>> cropHyperslabs(const std::string& path, const volume::GridVolume& cropped,
                                              const std::vector<std::string>& heightVariables);

/// What a probe measured.
struct LoadProbe {
  double medianMs = 0.0;
  std::uint64_t bytes = 0;  ///< reader: GridVolume::bytesRead; floor: elements x stored size
  double peakRssMb = 0.0;   ///< VmHWM of the child when it finished
  std::size_t columns = 0, levels = 0;
  std::string error;
};

/// One case of the load table.
struct LoadCase {
  std::string grid, name;
  LoadProbe reader, floor;  ///< reader.medianMs < 0: not measured (whole variable: floor only)
  bool hasReader = true;
};

/// The probe itself (what the child runs): `job` JSON {"mode": "reader"|"floor"|"idle", "path",
/// "variable", "time", "crop": [S, N, W, E], "slabs": [...], "runs"}; writes the result JSON.
/// Returns the exit status.
int runLoadProbe(const std::string& jobFile, const std::string& resultFile);

/// Runs the load cases of a grid volume (its views' crops, the whole time step, the whole
/// variable, an idle process for the baseline) through `selfExe --load-probe`, `runs` timed runs
/// each (median; the page cache is warm after the first). Progress on `log`.
std::vector<LoadCase> measureGridLoads(const BenchVolume& volume, const std::vector<BenchView>& views,
                                       const std::string& selfExe, const std::string& workDir, int runs,
                                       std::ostream& log);

}  // namespace atmoglobe::bench
