#include <atmoglobe/bench/GridLoad.h>

#include <atmoglobe/bench/Format.h>
#include <atmoglobe/bench/Measure.h>
#include <atmoglobe/bench/Process.h>
#include <atmoglobe/io/NetcdfLock.h>
#include <atmoglobe/volume/GridReader.h>

#include <eccodes.h>
#include <netcdf.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <ostream>

namespace atmoglobe::bench {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

/// The file's index range [first, first + count) of an output axis read with `step` from `first`.
std::pair<std::size_t, std::size_t> fileRange(std::size_t first, int step, std::size_t count) {
  return step >= 0 ? std::pair{first, count} : std::pair{first + 1 - count, count};
}

/// VmHWM of this process (MB), from /proc/self/status.
double peakRssMb() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

std::string ncName(const std::string& variable) {
  return variable.empty() || variable[0] != '/' ? variable : variable.substr(1);
}

/// Reads the slabs with plain nc_get_vara (one open per run, as the reader opens the file once).
Result<std::uint64_t> readSlabs(const std::string& path, const std::vector<Hyperslab>& slabs) {
  const io::NetcdfLock lock;  // direct netCDF-C calls (io/NetcdfLock.h)
  int nc = -1;
  if (const int st = nc_open(path.c_str(), NC_NOWRITE, &nc); st != NC_NOERR)
    return makeError(path + ": " + nc_strerror(st));
  std::uint64_t bytes = 0;
  std::vector<char> buffer;
  for (const Hyperslab& s : slabs) {
    int var = -1;
    nc_type type = NC_NAT;
    std::size_t size = 0, n = 1;
    if (nc_inq_varid(nc, ncName(s.variable).c_str(), &var) != NC_NOERR || nc_inq_vartype(nc, var, &type) != NC_NOERR ||
        nc_inq_type(nc, type, nullptr, &size) != NC_NOERR) {
      nc_close(nc);
      return makeError(path + ": no variable " + s.variable);
    }
    for (std::size_t c : s.count) n *= c;
    buffer.resize(n * size);
    if (const int st = nc_get_vara(nc, var, s.start.data(), s.count.data(), buffer.data()); st != NC_NOERR) {
      nc_close(nc);
      return makeError(path + ": " + s.variable + ": " + nc_strerror(st));
    }
    bytes += n * size;
  }
  nc_close(nc);
  return bytes;
}

nlohmann::json slabsJson(const std::vector<Hyperslab>& slabs) {
  nlohmann::json a = nlohmann::json::array();
  for (const Hyperslab& s : slabs) a.push_back({{"variable", s.variable}, {"start", s.start}, {"count", s.count}});
  return a;
}

LoadProbe spawnProbe(const std::string& selfExe, const fs::path& dir, const std::string& name,
                     const nlohmann::json& job) {
  LoadProbe p;
  const fs::path jobFile = dir / (name + "-job.json"), resultFile = dir / (name + "-result.json");
  std::error_code ec;
  fs::remove(resultFile, ec);
  std::ofstream(jobFile) << job.dump(1);
  const ProgramExit exit =
      runProgram({selfExe, "bench", "--load-probe", fs::absolute(jobFile).string(), fs::absolute(resultFile).string()});
  std::ifstream in(resultFile);
  if (!exit.succeeded() || !in) {
    p.error = "probe " + name + ": " + exit.describe();
    return p;
  }
  try {
    nlohmann::json r;
    in >> r;
    p.medianMs = r.value("median_ms", 0.0);
    p.bytes = r.value("bytes", std::uint64_t{0});
    p.peakRssMb = r.value("peak_rss_mb", 0.0);
    p.columns = r.value("columns", std::size_t{0});
    p.levels = r.value("levels", std::size_t{0});
    p.error = r.value("error", "");
  } catch (const std::exception& e) {
    p.error = resultFile.string() + ": " + e.what();
  }
  return p;
}

}  // namespace

Result<std::vector<Hyperslab>> cropHyperslabs(const std::string& path, const volume::GridVolume& g,
                                              const std::vector<std::string>& heightVariables) {
  const io::NetcdfLock lock;  // direct netCDF-C calls (io/NetcdfLock.h)
  int nc = -1;
  if (const int st = nc_open(path.c_str(), NC_NOWRITE, &nc); st != NC_NOERR)
    return makeError(path + ": " + nc_strerror(st));
  std::vector<Hyperslab> out;
  std::vector<std::string> names = {g.variable};
  names.insert(names.end(), heightVariables.begin(), heightVariables.end());
  const auto [row0, rows] = fileRange(g.fileFirstRow, g.fileRowStep, g.ny);
  const auto [level0, levels] = fileRange(g.fileFirstLevel, g.fileLevelStep, g.nz);
  for (const std::string& name : names) {
    int var = -1, ndims = 0;
    int dims[NC_MAX_VAR_DIMS];
    if (nc_inq_varid(nc, ncName(name).c_str(), &var) != NC_NOERR || nc_inq_varndims(nc, var, &ndims) != NC_NOERR ||
        ndims < 2 || nc_inq_vardimid(nc, var, dims) != NC_NOERR) {
      nc_close(nc);
      return makeError(path + ": no variable " + name + " with 2 or more dimensions");
    }
    std::size_t fileColumns = 0;
    nc_inq_dimlen(nc, dims[ndims - 1], &fileColumns);
    // (time,) level, y, x for the variable and 3-D height sources; (time,) y, x for 2-D ones.
    const bool hasLevels = ndims >= 3 && (name == g.variable || ndims == 4);
    Hyperslab s;
    s.variable = name;
    s.start.assign(static_cast<std::size_t>(ndims), 0);
    s.count.assign(static_cast<std::size_t>(ndims), 1);
    if (ndims == 4 || (ndims == 3 && !hasLevels)) s.start[0] = g.timeIndex;
    if (hasLevels) s.start[ndims - 3] = level0, s.count[ndims - 3] = levels;
    s.start[ndims - 2] = row0, s.count[ndims - 2] = rows;
    // Columns: a crop across a global grid's seam wraps modulo the file's columns (two reads).
    const auto [col0, cols] = fileRange(g.fileFirstColumn, g.fileColumnStep, g.nx);
    if (g.fileColumnStep >= 0 && col0 + cols > fileColumns && cols <= fileColumns) {
      Hyperslab a = s, b = s;
      a.start[ndims - 1] = col0, a.count[ndims - 1] = fileColumns - col0;
      b.start[ndims - 1] = 0, b.count[ndims - 1] = col0 + cols - fileColumns;
      out.push_back(a), out.push_back(b);
    } else {
      s.start[ndims - 1] = col0, s.count[ndims - 1] = std::min(cols, fileColumns);
      out.push_back(s);
    }
  }
  nc_close(nc);
  return out;
}

namespace {

struct GribFloorMessage {
  std::string path;
  std::uint64_t offset = 0, length = 0;
};

/// The floor of a GRIB read: the messages read from their files and decoded by ecCodes (values
/// only). Returns the bytes read.
Result<std::uint64_t> decodeGribMessages(const std::vector<GribFloorMessage>& messages) {
  std::map<std::string, std::unique_ptr<FILE, decltype(&std::fclose)>> files;
  std::vector<unsigned char> buffer;
  std::vector<double> values;
  std::uint64_t total = 0;
  for (const auto& [path, offset, length] : messages) {
    auto it = files.find(path);
    if (it == files.end())
      it = files
               .emplace(path,
                        std::unique_ptr<FILE, decltype(&std::fclose)>(std::fopen(path.c_str(), "rb"), &std::fclose))
               .first;
    FILE* f = it->second.get();
    if (!f) return makeError(path + ": cannot be opened");
    buffer.resize(length);
    if (fseeko(f, static_cast<off_t>(offset), SEEK_SET) != 0 ||
        std::fread(buffer.data(), 1, buffer.size(), f) != buffer.size())
      return makeError(path + ": message at byte " + std::to_string(offset) + " cannot be read");
    std::unique_ptr<codes_handle, decltype(&codes_handle_delete)> h(
        codes_handle_new_from_message(nullptr, buffer.data(), buffer.size()), &codes_handle_delete);
    std::size_t n = 0;
    if (!h || codes_get_size(h.get(), "values", &n) != CODES_SUCCESS)
      return makeError(path + ": message at byte " + std::to_string(offset) + ": ecCodes cannot decode it");
    values.resize(n);
    if (codes_get_double_array(h.get(), "values", values.data(), &n) != CODES_SUCCESS)
      return makeError(path + ": message at byte " + std::to_string(offset) + ": values cannot be decoded");
    total += length;
  }
  return total;
}

}  // namespace

int runLoadProbe(const std::string& jobFile, const std::string& resultFile) {
  nlohmann::json job, result;
  try {
    std::ifstream(jobFile) >> job;
  } catch (const std::exception& e) {
    result["error"] = jobFile + ": " + e.what();
  }
  const std::string mode = job.value("mode", "idle"), path = job.value("path", "");
  const int runs = std::max(1, job.value("runs", 1));
  std::vector<double> ms;
  // `runs` timed calls of `read` (a Result: an error ends the runs), `record` keeping its figures.
  auto timeRuns = [&](const auto& read, const auto& record) {
    for (int r = 0; r < runs; ++r) {
      const auto t0 = Clock::now();
      auto got = read();
      ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      if (!got) {
        result["error"] = got.error();
        break;
      }
      record(*got);
    }
  };
  auto recordBytes = [&](std::uint64_t bytes) { result["bytes"] = bytes; };
  if (mode == "reader") {
    volume::GridReadOptions o;
    o.variable = job.value("variable", "");
    o.timeIndex = job.value("time", std::size_t{0});
    o.member = job.value("member", -1L);
    if (job.contains("crop")) {
      const auto& c = job["crop"];
      o.crop.southDeg = c[0], o.crop.northDeg = c[1], o.crop.westDeg = c[2], o.crop.eastDeg = c[3];
    }
    timeRuns([&] { return volume::readGridVolume(path, o); },
             [&](const volume::GridVolume& g) {
               result["bytes"] = g.bytesRead;
               result["columns"] = g.nx * g.ny;
               result["levels"] = g.nz;
             });
  } else if (mode == "grib-floor") {
    // Plain ecCodes: each message's bytes read at its offset and its values decoded, nothing else.
    std::vector<GribFloorMessage> messages;
    for (const auto& m : job["messages"])
      messages.push_back({m[0].get<std::string>(), m[1].get<std::uint64_t>(), m[2].get<std::uint64_t>()});
    timeRuns([&] { return decodeGribMessages(messages); }, recordBytes);
  } else if (mode == "floor") {
    std::vector<Hyperslab> slabs;
    for (const auto& s : job["slabs"])
      slabs.push_back(
          {s["variable"], s["start"].get<std::vector<std::size_t>>(), s["count"].get<std::vector<std::size_t>>()});
    timeRuns([&] { return readSlabs(path, slabs); }, recordBytes);
  }
  result["median_ms"] = ms.empty() ? 0.0 : median(ms);
  result["peak_rss_mb"] = peakRssMb();
  std::ofstream out(resultFile);
  out << result.dump(1);
  return out && !result.contains("error") ? 0 : 1;
}

std::vector<LoadCase> measureGridLoads(const BenchVolume& v, const std::vector<BenchView>& views,
                                       const std::string& selfExe, const std::string& workDir, int runs,
                                       std::ostream& log) {
  std::vector<LoadCase> cases;
  const fs::path dir = fs::path(workDir) / "load";
  std::error_code ec;
  fs::create_directories(dir, ec);
  const nlohmann::json base = {{"path", fs::absolute(v.path).string()},
                               {"variable", v.gridRead.variable},
                               {"time", v.gridRead.timeIndex},
                               {"member", v.gridRead.member},
                               {"runs", runs}};
  auto addCase = [&](const std::string& name, const volume::GridCrop* crop, const volume::GridVolume* read) {
    LoadCase c;
    c.grid = v.key;
    c.name = name;
    const std::string tag = v.key + "-" + std::to_string(cases.size());
    log << "load: " << v.key << " " << name << " ..." << std::flush;
    nlohmann::json job = base;
    job["mode"] = "reader";
    if (crop) job["crop"] = {crop->southDeg, crop->northDeg, crop->westDeg, crop->eastDeg};
    c.reader = spawnProbe(selfExe, dir, tag + "-reader", job);
    job = base;
    if (!read->gribMessagesRead.empty()) {
      // GRIB: the floor decodes the same messages with plain ecCodes.
      const auto& reads = read->gribMessagesRead;
      if (std::any_of(reads.begin(), reads.end(), [](const auto& m) { return m.compressed; })) {
        c.floor.error = "a gzip/bzip2 GRIB file has no plain-ecCodes floor (its offsets are in the unwrapped content)";
      } else {
        job["mode"] = "grib-floor";
        job["messages"] = nlohmann::json::array();
        for (const auto& m : reads) job["messages"].push_back({m.path, m.offset, m.length});
        c.floor = spawnProbe(selfExe, dir, tag + "-floor", job);
      }
    } else if (auto slabs = cropHyperslabs(v.path, *read, v.heightVariables); !slabs) {
      c.floor.error = slabs.error();
    } else {
      job["mode"] = "floor";
      job["slabs"] = slabsJson(*slabs);
      c.floor = spawnProbe(selfExe, dir, tag + "-floor", job);
    }
    log << " reader " << formatG(c.reader.medianMs, 4) << " ms, " << (read->gribMessagesRead.empty() ? "" : "ecCodes ")
        << "floor " << formatG(c.floor.medianMs, 4) << " ms\n";
    cases.push_back(c);
  };
  for (const BenchView& view : views) {
    if (view.volume != &v) continue;
    volume::GridReadOptions o = v.gridRead;
    o.crop = view.crop;
    auto cropped = volume::readGridVolume(v.path, o);  // for its file indices
    if (!cropped) continue;
    addCase(view.name + " crop", &view.crop, &*cropped);
  }
  addCase("whole time step", nullptr, v.grid.get());
  // The whole variable, every time step: the floor only (the reader reads one step); netCDF only.
  if (v.grid->gribMessagesRead.empty()) {
    LoadCase c;
    c.grid = v.key;
    c.name = "whole variable (all steps)";
    c.hasReader = false;
    const io::NetcdfLock lock;  // direct netCDF-C calls (io/NetcdfLock.h)
    int nc = -1, var = -1, ndims = 0, dims[NC_MAX_VAR_DIMS];
    if (nc_open(v.path.c_str(), NC_NOWRITE, &nc) == NC_NOERR) {
      if (nc_inq_varid(nc, ncName(v.grid->variable).c_str(), &var) == NC_NOERR &&
          nc_inq_varndims(nc, var, &ndims) == NC_NOERR && nc_inq_vardimid(nc, var, dims) == NC_NOERR) {
        Hyperslab s{v.grid->variable, std::vector<std::size_t>(static_cast<std::size_t>(ndims), 0), {}};
        for (int d = 0; d < ndims; ++d) {
          std::size_t n = 0;
          nc_inq_dimlen(nc, dims[d], &n);
          s.count.push_back(n);
        }
        nlohmann::json job = base;
        job["mode"] = "floor";
        job["slabs"] = slabsJson({s});
        log << "load: " << v.key << " whole variable ..." << std::flush;
        c.floor = spawnProbe(selfExe, dir, v.key + "-whole-floor", job);
        log << " " << formatG(c.floor.medianMs, 4) << " ms\n";
      }
      nc_close(nc);
    }
    cases.push_back(c);
  }
  {
    LoadCase c;
    c.grid = v.key;
    c.name = "idle process (baseline)";
    c.hasReader = false;
    nlohmann::json job = base;
    job["mode"] = "idle";
    c.floor = spawnProbe(selfExe, dir, v.key + "-idle", job);
    cases.push_back(c);
  }
  return cases;
}

}  // namespace atmoglobe::bench
