#pragma once
// NEXRAD Level II (Archive II, message 31) reader.
//
// File layout (NOAA ICD 2620010 / 2620002): a 24-byte volume header ("AR2V00xx." + extension
// number, Julian date and milliseconds of the volume start, ICAO site id), then LDM records: a
// 4-byte big-endian byte count (negative for the last record) and a bzip2 stream (an uncompressed
// record is accepted too). Inside, each message has a 12-byte CTM prefix and a 16-byte header;
// message 31 (digital radar data) is variable length, all others sit in 2432-byte frames.
//
// What the reader makes of it:
//   - site: VOL block latitude/longitude, antenna height = site height + feedhorn height (m above
//     mean sea level, HeightDatum::MeanSeaLevel);
//   - one sweep per elevation number (cut); fixed angle = the VCP (message 5) target angle of the
//     cut, or the mean ray elevation when the file has no VCP message;
//   - split cuts (the same angle scanned twice, e.g. a surveillance cut with REF/ZDR/PHI/RHO and a
//     Doppler cut with VEL/SW): a cut that lacks the requested moment is dropped, so the volume has
//     only sweeps holding the loaded field (REF: all 11 cuts of VCP 21; VEL: 9);
//   - moments REF, VEL, SW, ZDR, PHI, RHO, CFP: value = (raw - offset) / scale, raw 0 (below
//     threshold) -> kNoEcho, raw 1 (range folded: measured but ambiguous) -> kNoData; gates
//     beyond a ray's own gate count (rays of one cut may differ) -> kNoData;
//   - gate ranges are gate centres (the ICD's "range to centre of first gate").
// Legacy message-1 files (before 2008) are reported as unsupported.
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

/// Reads a NEXRAD Level II Archive II file (bzip2-compressed LDM records of message 31).
/// The default field (empty ReadOptions::fieldName) is REF. Errors name the file and the problem.
Result<RadarVolume> readNexradLevel2(const std::string& path, const ReadOptions& options);

/// The same on a file's content already in memory (a decompressed .gz/.bz2 wrapper); `label`
/// names it in messages ("FILE (gzip)") and becomes RadarVolume::sourcePath.
Result<RadarVolume> readNexradLevel2(const std::string& label, const std::vector<unsigned char>& bytes,
                                     const ReadOptions& options);

/// True when `bytes` (the first bytes of a file, at least 8) start like an Archive II file.
bool looksLikeNexradLevel2(const unsigned char* bytes, std::size_t size);

}  // namespace atmoglobe::volume
