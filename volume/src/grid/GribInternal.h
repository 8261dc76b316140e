#pragma once
// Internals of the GRIB side of the forecast-grid reader (not a public header): the index of a
// file's messages (GribIndex.cpp) and the reader and `info` built on it (GribReader.cpp). GRIB
// itself is decoded by ecCodes only; nothing here parses GRIB sections by hand.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/GridReader.h>

#include <eccodes.h>

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace atmoglobe::volume::grib {

/// One message of a GRIB file: where it is and the keys that place it in a variable.
struct GribMessage {
  std::uint64_t offset = 0, length = 0;  ///< bytes in the file's content (unwrapped from gzip/bzip2)
  std::string shortName, typeOfLevel, gridType;
  std::string name, units;                  ///< ecCodes' parameter name and units ("Temperature", "K")
  double level = 0;                         ///< key `level` (hPa for isobaricInhPa, Pa for isobaricInPa, m for heights)
  long dataDate = 0, dataTime = 0;          ///< reference time (YYYYMMDD, hhmm)
  long validityDate = 0, validityTime = 0;  ///< validity time (YYYYMMDD, hhmm)
  std::string stepRange;                    ///< "12", "0-6" (stepUnits)
  long endStep = 0;
  long number = -1;        ///< ensemble member; -1: the message has none
  std::uint32_t file = 0;  ///< which of GribIndex::files holds it (a set of files; not cached)
  long ni = 0, nj = 0;     ///< 0: missing (reduced grids)
  long points = 0;         ///< numberOfPoints (a reduced grid's size)
  long edition = 0;
};

/// The index of a file: every readable message, what was skipped, and where the index is kept.
struct GribIndex {
  std::string path;         ///< as given (a set: its spec, a directory, pattern or list)
  std::string compression;  ///< "none", "gzip", "bzip2" (a set: "none" unless every file is compressed alike)
  /// The files (one, or a set's, sorted) and whether each is gzip/bzip2.
  std::vector<std::string> files;
  std::vector<bool> fileCompressed;
  std::vector<GribMessage> messages;
  std::vector<std::string> warnings;  ///< damaged stretches skipped, naming the file and byte offset
  std::string cacheFile;              ///< "" when the index could not be written
  bool fromCache = false;             ///< read from the cache (no pass over the file)
};

/// True when the content of `path` (unwrapped from gzip/bzip2) starts with "GRIB".
bool hasGribSignature(const std::string& path);

/// The cache directory of atmoglobe: $ATMOGLOBE_CACHE_DIR, else $XDG_CACHE_HOME/atmoglobe, else
/// $HOME/.cache/atmoglobe ("" when none can be named).
std::string cacheDirectory();

/// The index of `path`: from the cache when an index of this file (absolute path, size and
/// modification time equal) is there and readable, else made by one pass over the file with
/// ecCodes and written to the cache atomically (temporary + rename; a failure to write is not an
/// error: the index is used without being kept). Error: the file cannot be read, or holds no
/// readable message.
Result<GribIndex> gribIndex(const std::string& path);

/// Whether `spec` names a set of files (a directory, a pattern or a comma-separated list, as a
/// radar set: volume/RadarVolumeSet.h) of which at least one is GRIB: read as one GRIB file.
bool isGribSet(const std::string& spec);
/// The index of `spec`: one file's (gribIndex), or the indexes of a set's files merged, each
/// message knowing its file (centres publish one file per step or parameter). Error: a file of
/// the set that is not GRIB (named), or one gribIndex refuses.
Result<GribIndex> gribIndexOf(const std::string& spec);

/// ecCodes' default context is shared: every call into ecCodes holds this lock (reads may run on
/// the loaders' threads). Taking it the first time also installs the handler of ecCodes' internal
/// checks (below).
std::mutex& ecCodesLock();

/// Thrown from inside ecCodes when one of its internal checks (`Assert`) fails on a damaged
/// message: ecCodes 2.28 would call abort() there (fuzz_grib found several such messages: a
/// bitmap section without its loader, a reduced grid with a row of no points). The handler throws
/// instead (ecCodes is C built with unwind tables, so the exception passes through its frames; what
/// ecCodes allocated for the message on the way is lost, a few KiB per damaged message). Every
/// caller of ecCodes catches it: the index skips the message with a warning, a read fails with an
/// error naming the message. what(): ecCodes' text ("ecCodes assertion failed: `...' in FILE:LINE").
class EcCodesCheckFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The bytes of messages of the index's files: read at their offsets (plain files) or from the
/// unwrapped content in memory (gzip/bzip2). Each message is read once per GribContent (a read
/// decodes a message for its grid and its values, a geopotential for values and heights) and
/// counted once.
class GribContent {
 public:
  static Result<GribContent> open(const GribIndex& index);
  /// The message's bytes (valid while this object lives). Error: the file changed or is
  /// shorter than the index says.
  Result<const std::vector<unsigned char>*> read(const GribMessage& m);
  /// Drops the kept bytes of `m` (a message decoded once and not needed again: the temperatures
  /// of a hydrostatic integration, one level at a time); read again, it is counted again.
  void forget(const GribMessage& m) { read_.erase({m.file, m.offset}); }
  std::uint64_t bytesRead() const { return bytesRead_; }
  /// Every read counted in bytesRead, in order.
  const std::vector<GridVolume::GribMessageRead>& reads() const { return reads_; }

 private:
  struct File {
    std::string path, label;
    bool compressed = false;
    std::vector<unsigned char> unwrapped;  ///< whole content of a compressed file
  };
  std::vector<File> files_;
  std::map<std::pair<std::uint32_t, std::uint64_t>, std::vector<unsigned char>> read_;  ///< by file, offset
  std::uint64_t bytesRead_ = 0;
  std::vector<GridVolume::GribMessageRead> reads_;
};

/// A projected grid's points (GribProjection.cpp): latitude and longitude (degrees) of file row r
/// (in scanning order) and column c at r * Ni + c, and the PROJ definition they came from.
struct ProjectedGrid {
  std::string definition;
  std::vector<double> latDeg, lonDeg;
};
/// Whether `gridType` (ecCodes' key) is one of the projected grids projectedGrid places.
bool isProjectedGrid(const std::string& gridType);
/// The points of the projected grid of message `h` (ecCodes handle, held under ecCodesLock())
/// from its projection keys through PROJ. Error naming `where`: a key missing, a projection PROJ
/// refuses, a point off the Earth.
Result<ProjectedGrid> projectedGrid(codes_handle* h, const std::string& gridType, long ni, long nj,
                                    const std::string& where);

/// readGridVolume and describeGridFile for GRIB files (GribReader.cpp).
Result<GridVolume> readGribVolume(const std::string& path, const GridReadOptions& options);
Result<GridFileInfo> describeGribFile(const std::string& path, const std::string& variable);
std::string describeGribText(const GridFileInfo& info);
std::string describeGribJson(const GridFileInfo& info);

}  // namespace atmoglobe::volume::grib
