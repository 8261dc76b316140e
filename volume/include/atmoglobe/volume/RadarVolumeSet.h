#pragma once
// Radar volumes split over files, assembled into one volume each.
//
// What is a set: a directory (its regular files, not recursive, hidden files skipped), a glob
// pattern ("dir/*.h5"), or a comma-separated list of files, directories and patterns (a path
// that exists as a file is always that one file, whatever characters it holds).
//
// Which files make one volume (content only, never names):
//   - every file is read for its metadata (RadarReader.h; no values);
//   - the same site: positions within positionToleranceMeters horizontally and
//     heightToleranceMeters vertically (site names are not compared: writers name one radar
//     differently, e.g. ODIM NOD:behel and WMO:06475);
//   - the same nominal time, within timeToleranceSeconds: a PVOL's (or CfRadial's, NEXRAD's)
//     volume time; for an ODIM SCAN file (one sweep of a cycle, whose /what time is often its own
//     end time) the start of the clock-aligned cycle of scanCycleSeconds holding its scan start
//     (datasetN/what startdate/starttime), e.g. 06:55:00Z for a scan started 06:56:27Z;
//   - NEXRAD real-time chunks (files that are bare LDM records, plus the one start chunk with the
//     volume header) form one volume (NexradReader.h, readNexradChunks); NEXRAD archives are
//     never merged with other files.
// Assembling a group: the fields are the union of the files' fields; the loaded field (asked for,
// else chooseDefaultField over the union) is decoded from the files that hold it only; sweeps
// come from those files, sorted by elevation; sweeps of the other files at elevations no
// field-holding file has are kept as no data (as the ODIM reader does); a second sweep at the
// same elevation (within 0.01 deg) from another file is dropped with a warning. Site: the first
// field-holding file's (the name of that file); time: the earliest sweep start (else file time).
//
// Warnings (RadarVolume::warnings) say what was assembled and what looks missing: files naming
// the site differently, each file's own reader warnings (prefixed with its name), a cycle or
// volume with fewer elevations or fields than the fullest one of the same site in the set (naming
// them), and a gap in a SCAN cycle long enough to hold a scan (at its start, between scans or at
// its end). Files of different sites or times are never merged: readRadarVolumeGroups returns
// them as separate volumes, readRadarVolumeSet fails listing them (or, with several times of ONE
// site and latestWhenSeveralTimes, reads the latest and says so).
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <string>
#include <vector>

namespace atmoglobe::volume {

struct RadarSetOptions {
  ReadOptions read;                        ///< field, values or metadata only, NEXRAD site list
  double positionToleranceMeters = 250.0;  ///< one site: horizontal distance of the positions
  double heightToleranceMeters = 50.0;     ///< one site: antenna heights
  double timeToleranceSeconds = 60.0;      ///< one volume: nominal times
  int scanCycleSeconds = 300;              ///< ODIM SCAN files: length of the clock-aligned volume cycle
  /// readRadarVolumeSet on several volumes of one site at different times: read the latest (with
  /// a warning naming the others) instead of failing.
  bool latestWhenSeveralTimes = true;
  /// Names the set in messages and RadarVolume::sourcePath; empty: the first file and a count.
  std::string label;
};

/// True when `spec` names a set of files rather than one file: not an existing regular file, and
/// an existing directory, a pattern (* ? [) or a comma-separated list.
bool isRadarFileSet(const std::string& spec);

/// The files a set spec names, each part sorted by name, duplicates removed. Errors: an empty
/// directory, a pattern matching no file, a missing path (each named).
Result<std::vector<std::string>> expandRadarPaths(const std::string& spec);

/// Every volume the files hold, assembled (sorted by site, then time). Errors name the file.
Result<std::vector<RadarVolume>> readRadarVolumeGroups(const std::vector<std::string>& paths,
                                                       const RadarSetOptions& options);

/// The ONE volume the files hold, assembled. Files of several sites or times: an error listing
/// the volumes and their files (but see latestWhenSeveralTimes).
Result<RadarVolume> readRadarVolumeSet(const std::vector<std::string>& paths, const RadarSetOptions& options);

}  // namespace atmoglobe::volume
