#pragma once
// NEXRAD Level II reader: Archive II files (message 31, and the legacy message-1 layout) and
// real-time chunk sets.
//
// File layout (NOAA ICD 2620010 / 2620002): a 24-byte volume header ("AR2V00xx." or, in old
// files, "ARCHIVE2." + extension number, Julian date and milliseconds of the volume start, ICAO
// site id), then LDM records: a 4-byte big-endian byte count (negative for the last record) and a
// bzip2 stream (an uncompressed record is accepted too). Inside, each message has a 12-byte CTM
// prefix and a 16-byte header; message 31 (digital radar data) is variable length, all others
// sit in 2432-byte frames. Legacy files (ARCHIVE2 / AR2V0001 headers, before 2008) hold the
// frames uncompressed right after the header, with message-1 radials (or LDM records of them).
//
// What the reader makes of it:
//   - site: VOL block latitude/longitude, antenna height = site height + feedhorn height (m above
//     mean sea level, HeightDatum::MeanSeaLevel). Message-1 files give no position: it comes
//     from a NEXRAD site list by the header's ICAO id (ReadOptions::nexradSiteList, else
//     $ATMOGLOBE_NEXRAD_SITES; ground elevation + tower height), RadarSite::locationSource says
//     so, and without a list the read fails saying how to give one;
//   - one sweep per elevation number (cut); fixed angle = the VCP (message 5) target angle of the
//     cut, or the mean ray elevation when the file has no VCP message;
//   - split cuts (the same angle scanned twice, e.g. a surveillance cut with REF/ZDR/PHI/RHO and a
//     Doppler cut with VEL/SW): a cut that lacks the requested moment is dropped, so the volume has
//     only sweeps holding the loaded field (REF: all 11 cuts of VCP 21; VEL: 9); a warning names them;
//   - moments REF, VEL, SW, ZDR, PHI, RHO, CFP: value = (raw - offset) / scale, raw 0 (below
//     threshold) -> kNoEcho, raw 1 (range folded: measured but ambiguous) -> kNoData; gates
//     beyond a ray's own gate count (rays of one cut may differ) -> kNoData. Message 1: REF from
//     the surveillance gates, VEL and SW from the Doppler gates, each with its own first-gate
//     range and spacing (so REF and VEL sweeps of one cut differ in geometry); fixed ICD scalings
//     REF (raw - 66) / 2 dBZ, VEL (raw - 129) / 2 m/s (raw - 129 at 1 m/s resolution), SW
//     (raw - 129) / 2 m/s;
//   - gate ranges are gate centres (the ICD's "range to centre of first gate");
//   - completeness: each radial's status (start/end of elevation, end of volume) and azimuth
//     number. A radial repeating an (elevation, azimuth number) pair is dropped (warning). A cut
//     without its end radial or with missing azimuth numbers is partial (Sweep::complete false):
//     the azimuths it has not reached are filled with no-data rays at its nominal spacing, so no
//     renderer interpolates across them; a warning lists the complete cuts, the partial ones and
//     the cuts of the VCP not in the data yet (a volume in progress).
// Every pointer and count is checked against the record it sits in; a record may not decompress
// beyond kNexradMaxRecordBytes.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <cstddef>
#include <string>
#include <vector>

namespace atmoglobe::volume {

/// Largest decompressed LDM record accepted (real records are under 2 MiB).
inline constexpr std::size_t kNexradMaxRecordBytes = std::size_t{64} << 20;

/// Reads a NEXRAD Level II Archive II file (bzip2-compressed LDM records of message 31, or a legacy
/// message-1 file).
/// The default field (empty ReadOptions::fieldName) is REF. Errors name the file and the problem.
Result<RadarVolume> readNexradLevel2(const std::string& path, const ReadOptions& options);

/// The same on a file's content already in memory (a decompressed .gz/.bz2 wrapper); `label`
/// names it in messages ("FILE (gzip)") and becomes RadarVolume::sourcePath.
Result<RadarVolume> readNexradLevel2(const std::string& label, const std::vector<unsigned char>& bytes,
                                     const ReadOptions& options);

/// True when `bytes` (the first bytes of a file, at least 8) start like an Archive II file
/// ("AR2V00" or "ARCHIVE2": also a real-time start chunk).
bool looksLikeNexradLevel2(const unsigned char* bytes, std::size_t size);

/// True when `bytes` (at least 7) start like a real-time intermediate or end chunk: an LDM
/// record (4-byte big-endian size, then "BZh").
bool looksLikeNexradChunk(const unsigned char* bytes, std::size_t size);

/// Reads the real-time chunks of one volume (the feed's `..._NNN-S` start chunk with the volume
/// header, `-I` intermediate and `-E` end chunks: LDM records of message 31) as one volume. Exactly
/// one start chunk is required; the others are put in scan order by the time of their first
/// radial (content, not names). A volume in progress (no end chunk yet, or a chunk missing) is
/// read with its warnings saying which cuts are complete. `label` names the set in messages and
/// becomes sourcePath; sourceFiles lists the chunks in the order read.
Result<RadarVolume> readNexradChunks(const std::vector<std::string>& paths, const std::string& label,
                                     const ReadOptions& options);

}  // namespace atmoglobe::volume
