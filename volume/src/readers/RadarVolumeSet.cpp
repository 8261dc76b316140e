#include <atmoglobe/volume/RadarVolumeSet.h>

#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/NexradReader.h>
#include <atmoglobe/volume/RadarReader.h>

#include <glob.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <system_error>

namespace atmoglobe::volume {

namespace {

namespace fs = std::filesystem;

bool hasPatternChars(const std::string& s) { return s.find_first_of("*?[") != std::string::npos; }

bool isRegularFile(const std::string& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}
bool isDirectory(const std::string& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string isoFromEpoch(double seconds) {
  if (!std::isfinite(seconds)) return "(no time)";
  const auto t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string baseName(const std::string& p) { return fs::path(p).filename().string(); }

/// Horizontal distance of two positions (m): equirectangular, enough for a tolerance of
/// hundreds of metres (error well under 1 % at such distances).
double horizontalMeters(const RadarSite& a, const RadarSite& b) {
  constexpr double kMetersPerDeg = 111320.0;
  const double dLat = (a.latDeg - b.latDeg) * kMetersPerDeg;
  double dLonDeg = std::remainder(a.lonDeg - b.lonDeg, 360.0);
  const double dLon = dLonDeg * kMetersPerDeg * std::cos((a.latDeg + b.latDeg) * 0.5 * M_PI / 180.0);
  return std::hypot(dLat, dLon);
}

/// One volume's worth of files as read for grouping: a file, or a NEXRAD chunk set.
struct Entry {
  std::vector<std::string> paths;
  RadarVolume meta;  ///< metadata only
  bool nexrad = false, chunks = false;
  double nominal = std::numeric_limits<double>::quiet_NaN();
  double scanStart = std::numeric_limits<double>::quiet_NaN();  ///< earliest sweep start, else volume time
};

struct Group {
  std::vector<const Entry*> entries;
  std::vector<std::string> warnings;  ///< set-level, found on metadata
  double nominal() const { return entries.front()->nominal; }
  const RadarSite& site() const { return entries.front()->meta.site; }
  bool scanCycle() const {
    return std::all_of(entries.begin(), entries.end(), [](const Entry* e) { return e->meta.singleScanFile; });
  }
  std::vector<double> elevations() const {
    std::vector<double> out;
    for (const Entry* e : entries)
      for (const Sweep& s : e->meta.sweeps) {
        if (std::none_of(out.begin(), out.end(), [&](double x) { return std::fabs(x - s.fixedAngleDeg) < 0.01; }))
          out.push_back(s.fixedAngleDeg);
      }
    std::sort(out.begin(), out.end());
    return out;
  }
  std::vector<std::string> fieldNames() const {
    std::vector<std::string> out;
    for (const Entry* e : entries)
      for (const FieldInfo& f : e->meta.fields)
        if (std::find(out.begin(), out.end(), f.name) == out.end()) out.push_back(f.name);
    return out;
  }
  std::vector<std::string> files() const {
    std::vector<std::string> out;
    for (const Entry* e : entries) out.insert(out.end(), e->paths.begin(), e->paths.end());
    return out;
  }
};

std::string angleList(const std::vector<double>& v) {
  std::string s;
  for (double a : v) s += (s.empty() ? "" : ", ") + fmt("%.2f", a);
  return s + " deg";
}

std::string joinNames(const std::vector<std::string>& v, std::size_t max = 6) {
  std::string s;
  for (std::size_t i = 0; i < v.size() && i < max; ++i) s += (s.empty() ? "" : ", ") + baseName(v[i]);
  if (v.size() > max) s += ", ... (" + std::to_string(v.size()) + " files)";
  return s;
}

std::string defaultLabel(const std::vector<std::string>& paths) {
  if (paths.size() == 1) return paths.front();
  return paths.front() + " and " + std::to_string(paths.size() - 1) + " more file" + (paths.size() > 2 ? "s" : "");
}

std::string describeGroup(const Group& g) {
  const RadarSite& s = g.site();
  return (s.name.empty() ? std::string("(unnamed site)") : s.name) + " at " + fmt("%.4f", s.latDeg) + ", " +
         fmt("%.4f", s.lonDeg) + ", " + isoFromEpoch(g.nominal()) + ": " + joinNames(g.files());
}

Result<std::vector<Entry>> collectEntries(const std::vector<std::string>& paths, const RadarSetOptions& options,
                                          const std::string& label) {
  if (paths.empty()) return makeError(label + ": no radar files given");
  std::vector<Entry> entries;
  std::vector<std::string> nexradPieces;
  bool anyChunk = false;
  for (const std::string& p : paths) {
    std::ifstream in(p, std::ios::binary);
    if (!in) return makeError(p + ": cannot open file");
    std::array<unsigned char, 8> head{};
    in.read(reinterpret_cast<char*>(head.data()), 8);
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n >= 8 && looksLikeNexradLevel2(head.data(), n)) {
      nexradPieces.push_back(p);
      continue;
    }
    if (n >= 7 && looksLikeNexradChunk(head.data(), n)) {
      nexradPieces.push_back(p);
      anyChunk = true;
      continue;
    }
    ReadOptions ro = options.read;
    ro.loadValues = false;
    ro.fieldName.clear();
    auto meta = readRadarVolume(p, ro);
    if (!meta) return meta.forwardError();
    Entry e;
    e.paths = {p};
    e.meta = std::move(*meta);
    entries.push_back(std::move(e));
  }
  ReadOptions ro = options.read;
  ro.loadValues = false;
  ro.fieldName.clear();
  if (anyChunk) {
    auto meta = readNexradChunks(nexradPieces, label, ro);
    if (!meta) return meta.forwardError();
    Entry e;
    e.paths = meta->sourceFiles;
    e.meta = std::move(*meta);
    e.nexrad = e.chunks = true;
    entries.push_back(std::move(e));
  } else {
    for (const std::string& p : nexradPieces) {
      auto meta = readRadarVolume(p, ro);
      if (!meta) return meta.forwardError();
      Entry e;
      e.paths = {p};
      e.meta = std::move(*meta);
      e.nexrad = true;
      entries.push_back(std::move(e));
    }
  }
  for (Entry& e : entries) {
    double earliest = std::numeric_limits<double>::quiet_NaN();
    for (const Sweep& s : e.meta.sweeps) {
      const double t = iso8601ToEpochSeconds(s.startTimeIso8601);
      if (std::isfinite(t) && !(t >= earliest)) earliest = t;
    }
    const double volumeTime = iso8601ToEpochSeconds(e.meta.timeIso8601);
    e.scanStart = std::isfinite(earliest) ? earliest : volumeTime;
    if (e.meta.singleScanFile && std::isfinite(e.scanStart) && options.scanCycleSeconds > 0) {
      const double cycle = options.scanCycleSeconds;
      e.nominal = std::floor(e.scanStart / cycle) * cycle;
    } else {
      e.nominal = volumeTime;
    }
  }
  std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    if (std::isnan(a.nominal) != std::isnan(b.nominal)) return std::isnan(b.nominal);
    if (a.nominal != b.nominal) return a.nominal < b.nominal;
    return a.paths.front() < b.paths.front();
  });
  return entries;
}

bool sameSite(const RadarSite& a, const RadarSite& b, const RadarSetOptions& o) {
  return horizontalMeters(a, b) <= o.positionToleranceMeters &&
         std::fabs(a.antennaHeightMeters - b.antennaHeightMeters) <= o.heightToleranceMeters;
}

std::vector<Group> groupEntries(const std::vector<Entry>& entries, const RadarSetOptions& o) {
  std::vector<Group> groups;
  for (const Entry& e : entries) {
    Group* target = nullptr;
    if (!e.nexrad && std::isfinite(e.nominal)) {
      for (Group& g : groups) {
        const Entry& first = *g.entries.front();
        if (first.nexrad || !std::isfinite(first.nominal)) continue;
        if (sameSite(first.meta.site, e.meta.site, o) &&
            std::fabs(first.nominal - e.nominal) <= o.timeToleranceSeconds) {
          target = &g;
          break;
        }
      }
    }
    if (target == nullptr) {
      groups.emplace_back();
      target = &groups.back();
    }
    target->entries.push_back(&e);
  }
  // Set-level findings, on metadata.
  for (Group& g : groups) {
    // Site names that differ between files matched by position.
    std::vector<std::string> names;
    for (const Entry* e : g.entries)
      if (std::find(names.begin(), names.end(), e->meta.site.name) == names.end()) names.push_back(e->meta.site.name);
    if (names.size() > 1) {
      std::string list;
      for (std::size_t i = 0; i < g.entries.size(); ++i)
        list += (i ? ", " : "") + std::string("'") + g.entries[i]->meta.site.name + "' in " +
                baseName(g.entries[i]->paths.front());
      double worst = 0;
      for (const Entry* e : g.entries) worst = std::max(worst, horizontalMeters(e->meta.site, g.site()));
      g.warnings.push_back("the files name the site differently (" + list + "); matched by position (within " +
                           fmt("%.0f", worst) + " m) and time");
    }
    if (g.entries.size() > 1 && g.scanCycle()) {
      g.warnings.push_back("assembled from " + std::to_string(g.entries.size()) + " single-scan (SCAN) files of the " +
                           std::to_string(o.scanCycleSeconds / 60) + "-minute cycle starting " +
                           isoFromEpoch(g.nominal()));
    } else if (g.entries.size() > 1) {
      g.warnings.push_back("assembled from " + std::to_string(g.entries.size()) + " files of one scan (" +
                           isoFromEpoch(g.nominal()) + ")");
    }
  }
  // Missing elevations or fields against the fullest volume of the same site and kind.
  for (Group& g : groups) {
    const Group* fullest = nullptr;
    for (const Group& h : groups) {
      if (&h == &g || h.scanCycle() != g.scanCycle() || !sameSite(h.site(), g.site(), o)) continue;
      if (!fullest || h.elevations().size() > fullest->elevations().size()) fullest = &h;
    }
    const auto mine = g.elevations();
    if (fullest && fullest->elevations().size() > mine.size()) {
      std::vector<double> absent;
      for (double a : fullest->elevations())
        if (std::none_of(mine.begin(), mine.end(), [&](double x) { return std::fabs(x - a) < 0.01; }))
          absent.push_back(a);
      g.warnings.push_back(std::string("incomplete ") + (g.scanCycle() ? "cycle" : "volume") + ": " +
                           std::to_string(mine.size()) + " elevations (" + angleList(mine) + ") where the " +
                           isoFromEpoch(fullest->nominal()) + " one of this site has " +
                           std::to_string(fullest->elevations().size()) + "; not here: " + angleList(absent));
    }
    const auto myFields = g.fieldNames();
    for (const Group& h : groups) {
      if (&h == &g || !sameSite(h.site(), g.site(), o)) continue;
      std::vector<std::string> absent;
      for (const std::string& f : h.fieldNames())
        if (std::find(myFields.begin(), myFields.end(), f) == myFields.end()) absent.push_back(f);
      if (!absent.empty()) {
        std::string list;
        for (const std::string& f : absent) list += (list.empty() ? "" : ", ") + f;
        g.warnings.push_back("no " + list + " in this volume, where the " + isoFromEpoch(h.nominal()) +
                             " one of this site has it (a file of this volume may be missing)");
        break;
      }
    }
    // A gap in a SCAN cycle long enough to hold one of its scans.
    if (g.scanCycle() && o.scanCycleSeconds > 0) {
      struct Span {
        double start, end;
      };
      std::vector<Span> spans;
      double shortest = std::numeric_limits<double>::infinity();
      for (const Entry* e : g.entries)
        for (const Sweep& s : e->meta.sweeps) {
          const double a = iso8601ToEpochSeconds(s.startTimeIso8601), b = iso8601ToEpochSeconds(s.endTimeIso8601);
          if (std::isfinite(a) && std::isfinite(b) && b >= a) {
            spans.push_back({a, b});
            shortest = std::min(shortest, b - a);
          }
        }
      if (!spans.empty() && shortest > 0) {
        std::sort(spans.begin(), spans.end(), [](const Span& x, const Span& y) { return x.start < y.start; });
        const double cycleStart = g.nominal(), cycleEnd = g.nominal() + o.scanCycleSeconds;
        std::vector<std::string> gaps;
        double previous = cycleStart;
        for (const Span& s : spans) {
          if (s.start - previous >= shortest) gaps.push_back(isoFromEpoch(previous) + " to " + isoFromEpoch(s.start));
          previous = std::max(previous, s.end);
        }
        if (cycleEnd - previous >= shortest) gaps.push_back(isoFromEpoch(previous) + " to " + isoFromEpoch(cycleEnd));
        if (!gaps.empty()) {
          std::string list;
          for (const std::string& x : gaps) list += (list.empty() ? "" : "; ") + x;
          g.warnings.push_back("the cycle has no scan from " + list + ", time enough for one (the shortest here took " +
                               fmt("%.0f", shortest) + " s): a scan may be missing");
        }
      }
    }
  }
  return groups;
}

/// Reads one group with values (or metadata only) and assembles it.
Result<RadarVolume> assemble(const Group& g, const RadarSetOptions& o, const std::string& label) {
  const ReadOptions& ro = o.read;
  if (g.entries.size() == 1) {
    const Entry& e = *g.entries.front();
    Result<RadarVolume> v = e.meta;
    if (ro.loadValues || !ro.fieldName.empty()) {
      v = e.chunks ? readNexradChunks(e.paths, label, ro) : readRadarVolume(e.paths.front(), ro);
      if (!v) return v;
    }
    if (e.chunks) v->sourcePath = label;
    v->warnings.insert(v->warnings.begin(), g.warnings.begin(), g.warnings.end());
    return v;
  }

  std::vector<FieldInfo> fields;
  for (const Entry* e : g.entries)
    for (const FieldInfo& f : e->meta.fields)
      if (std::none_of(fields.begin(), fields.end(), [&](const FieldInfo& x) { return x.name == f.name; }))
        fields.push_back(f);
  std::string loaded;
  if (!fields.empty()) {
    auto index = selectField(fields, ro.fieldName);
    if (!index) return makeError(label + ": " + index.error());
    loaded = fields[*index].name;
  }

  RadarVolume out;
  out.fields = fields;
  out.sourcePath = label;
  std::vector<std::string> formats;
  std::vector<std::string> readerWarnings;
  std::vector<std::string> duplicates;
  const Entry* siteFrom = nullptr;
  double earliest = std::numeric_limits<double>::quiet_NaN();
  // Files holding the loaded field first (their sweeps win), then the others.
  std::vector<const Entry*> order;
  for (const Entry* e : g.entries)
    if (std::any_of(e->meta.fields.begin(), e->meta.fields.end(), [&](const FieldInfo& f) { return f.name == loaded; }))
      order.push_back(e);
  const std::size_t holding = order.size();
  for (const Entry* e : g.entries)
    if (std::find(order.begin(), order.end(), e) == order.end()) order.push_back(e);

  std::vector<Sweep> sweeps;
  std::vector<std::string> sweepFile;
  std::size_t emptySweeps = 0;
  std::vector<std::string> emptyFrom;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Entry& e = *order[i];
    const bool holds = i < holding;
    RadarVolume v;
    if (holds && ro.loadValues) {
      ReadOptions one = ro;
      one.fieldName = loaded;
      auto r = e.chunks ? readNexradChunks(e.paths, label, one) : readRadarVolume(e.paths.front(), one);
      if (!r) return r.forwardError();
      v = std::move(*r);
    } else {
      v = e.meta;
    }
    if (std::find(formats.begin(), formats.end(), v.format) == formats.end()) formats.push_back(v.format);
    for (const std::string& w : v.warnings) readerWarnings.push_back(baseName(e.paths.front()) + ": " + w);
    if (holds && siteFrom == nullptr) {
      siteFrom = &e;
      out.site = v.site;
      out.beamWidthDeg = v.beamWidthDeg;
      out.loadedField = v.loadedField;
    }
    if (out.beamWidthDeg <= 0) out.beamWidthDeg = v.beamWidthDeg;
    if (std::isfinite(v.nyquistVelocityMps) && !(v.nyquistVelocityMps <= out.nyquistVelocityMps))
      out.nyquistVelocityMps = v.nyquistVelocityMps;
    if (std::isfinite(e.scanStart) && !(e.scanStart >= earliest)) earliest = e.scanStart;
    for (Sweep& s : v.sweeps) {
      bool duplicate = false;
      for (std::size_t k = 0; k < sweeps.size(); ++k) {
        if (std::fabs(sweeps[k].fixedAngleDeg - s.fixedAngleDeg) < 0.01 && sweepFile[k] != e.paths.front()) {
          duplicate = true;
          if (holds)
            duplicates.push_back(fmt("%.2f", s.fixedAngleDeg) + " deg in " + baseName(e.paths.front()) + " (kept " +
                                 baseName(sweepFile[k]) + "'s)");
          break;
        }
      }
      if (duplicate) continue;
      if (!holds) {
        if (ro.loadValues) s.values.assign(s.rayCount() * s.gateCount, kNoData);
        ++emptySweeps;
        if (std::find(emptyFrom.begin(), emptyFrom.end(), e.paths.front()) == emptyFrom.end())
          emptyFrom.push_back(e.paths.front());
      }
      sweeps.push_back(std::move(s));
      sweepFile.push_back(e.paths.front());
    }
  }
  if (siteFrom == nullptr) {
    // No file holds a field: metadata of the first file.
    out.site = g.entries.front()->meta.site;
    out.beamWidthDeg = g.entries.front()->meta.beamWidthDeg;
  }
  out.sweeps = std::move(sweeps);
  for (std::size_t i = 0; i < formats.size(); ++i) out.format += (i ? " + " : "") + formats[i];
  out.timeIso8601 = std::isfinite(earliest) ? isoFromEpoch(earliest) : g.entries.front()->meta.timeIso8601;
  out.sourceFiles = g.files();
  out.warnings = g.warnings;
  if (!duplicates.empty()) {
    std::string list;
    for (const std::string& d : duplicates) list += (list.empty() ? "" : "; ") + d;
    out.warnings.push_back("sweeps at an elevation another file already gave are dropped: " + list);
  }
  if (emptySweeps > 0 && !loaded.empty()) {
    out.warnings.push_back(std::to_string(emptySweeps) + " sweeps of files without " + loaded + " (" +
                           joinNames(emptyFrom) + "), at elevations no file with it has, are kept as no data");
  }
  out.warnings.insert(out.warnings.end(), readerWarnings.begin(), readerWarnings.end());
  // Files come in scan order; sorting their sweeps by elevation is the assembly, not a repair.
  std::stable_sort(out.sweeps.begin(), out.sweeps.end(),
                   [](const Sweep& a, const Sweep& b) { return a.fixedAngleDeg < b.fixedAngleDeg; });
  return out;
}

}  // namespace

bool isRadarFileSet(const std::string& spec) {
  if (spec.empty() || isRegularFile(spec)) return false;
  return isDirectory(spec) || hasPatternChars(spec) || spec.find(',') != std::string::npos;
}

Result<std::vector<std::string>> expandRadarPaths(const std::string& spec) {
  std::vector<std::string> out;
  std::set<std::string> seen;
  auto add = [&](const std::string& p) {
    if (seen.insert(p).second) out.push_back(p);
  };
  auto expandOne = [&](const std::string& part) -> Status {
    if (part.empty()) return makeError(spec + ": an empty entry in the list of radar files");
    if (isRegularFile(part)) {
      add(part);
      return Ok{};
    }
    if (isDirectory(part)) {
      std::vector<std::string> files;
      std::error_code ec;
      for (const auto& d : fs::directory_iterator(part, ec)) {
        const std::string name = d.path().filename().string();
        if (name.empty() || name[0] == '.') continue;
        if (d.is_regular_file(ec)) files.push_back(d.path().string());
      }
      if (ec) return makeError(part + ": cannot list the directory: " + ec.message());
      if (files.empty()) return makeError(part + ": the directory holds no files");
      std::sort(files.begin(), files.end());
      for (const std::string& f : files) add(f);
      return Ok{};
    }
    if (hasPatternChars(part)) {
      glob_t g{};
      const int rc = ::glob(part.c_str(), 0, nullptr, &g);
      std::vector<std::string> files;
      if (rc == 0) {
        for (std::size_t i = 0; i < g.gl_pathc; ++i)
          if (isRegularFile(g.gl_pathv[i])) files.push_back(g.gl_pathv[i]);
      }
      globfree(&g);
      if (rc != 0 && rc != GLOB_NOMATCH) return makeError(part + ": cannot expand the pattern");
      if (files.empty()) return makeError(part + ": no file matches the pattern");
      std::sort(files.begin(), files.end());
      for (const std::string& f : files) add(f);
      return Ok{};
    }
    return makeError(part + ": no such file or directory");
  };
  if (isRegularFile(spec) || spec.find(',') == std::string::npos) {
    if (Status s = expandOne(spec); !s) return s.forwardError();
    return out;
  }
  std::size_t pos = 0;
  while (pos <= spec.size()) {
    const std::size_t comma = std::min(spec.find(',', pos), spec.size());
    if (Status s = expandOne(spec.substr(pos, comma - pos)); !s) return s.forwardError();
    pos = comma + 1;
  }
  return out;
}

Result<std::vector<RadarVolume>> readRadarVolumeGroups(const std::vector<std::string>& paths,
                                                       const RadarSetOptions& options) {
  const std::string label = options.label.empty() ? defaultLabel(paths) : options.label;
  auto entries = collectEntries(paths, options, label);
  if (!entries) return entries.forwardError();
  const std::vector<Group> groups = groupEntries(*entries, options);
  std::vector<RadarVolume> out;
  for (const Group& g : groups) {
    const std::string groupLabel =
        label + " [" + (g.site().name.empty() ? "" : g.site().name + " ") + isoFromEpoch(g.nominal()) + "]";
    auto v = assemble(g, options, groups.size() == 1 ? label : g.entries.size() == 1 ? g.files().front() : groupLabel);
    if (!v) return v.forwardError();
    out.push_back(std::move(*v));
  }
  return out;
}

Result<RadarVolume> readRadarVolumeSet(const std::vector<std::string>& paths, const RadarSetOptions& options) {
  const std::string label = options.label.empty() ? defaultLabel(paths) : options.label;
  auto entries = collectEntries(paths, options, label);
  if (!entries) return entries.forwardError();
  const std::vector<Group> groups = groupEntries(*entries, options);
  if (groups.size() == 1) return assemble(groups.front(), options, label);
  const bool oneSite = std::all_of(groups.begin(), groups.end(), [&](const Group& g) {
    return !g.entries.front()->nexrad && sameSite(g.site(), groups.front().site(), options);
  });
  std::string list;
  for (const Group& g : groups) list += "\n  " + describeGroup(g);
  if (!oneSite || !options.latestWhenSeveralTimes) {
    return makeError(label + ": the files hold " + std::to_string(groups.size()) + " volumes (" +
                     (oneSite ? "one site at different times" : "different sites or times") +
                     "), which are never merged; give the files of one volume:" + list);
  }
  const Group* latest = &groups.front();
  for (const Group& g : groups)
    if (std::isfinite(g.nominal()) && !(g.nominal() <= latest->nominal())) latest = &g;
  auto v = assemble(*latest, options, label);
  if (!v) return v;
  v->warnings.insert(v->warnings.begin(), "the files hold " + std::to_string(groups.size()) +
                                              " volumes of this site at different times; the latest (" +
                                              isoFromEpoch(latest->nominal()) +
                                              ") is read (name one volume's files to read another):" + list);
  return v;
}

}  // namespace atmoglobe::volume
