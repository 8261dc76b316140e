#pragma once
// Leonardo/Gematronik Rainbow 5 volume reader (".vol": scan types vol/azi = PPI, ele = RHI).
//
// Layout (Rainbow 5 file format; wradlib/xradar documentation): an XML description up to the line
// "<!-- END XML -->", then binary BLOBs: `<BLOB blobid="N" size="S" compression="qt">`, a newline,
// S bytes, `</BLOB>`. A "qt" BLOB is Qt's qCompress: a 4-byte big-endian uncompressed size, then a
// zlib stream. XML: <volume version datetime type> / <scan name date time> / <pargroup> (defaults)
// and one <slice> per sweep; a slice's settings that it does not give come from slice 0, then from
// the pargroup. Per slice: posangle (elevation of a PPI, azimuth of an RHI), start_range and
// stoprange (km), rangestep (km), anglestep (deg), antdirection; <slicedata date time> holds
// <rayinfo refid="startangle" blobid rays depth> (and optionally stopangle) and one <rawdata
// blobid rays bins type min max depth> per moment. <sensorinfo> (or <radarinfo>) gives lat, lon,
// alt (m above sea level), beamwidth, wavelen as child elements or attributes.
//
// What the reader makes of it:
//   - ray angles: BLOB values (big-endian, `depth` bits) x 360 / 2^depth; with stop angles the
//     circular midpoint, else start + anglestep / 2 (minus for antdirection 1); the other angle is
//     posangle;
//   - gates: first gate centre = start_range + rangestep / 2, spacing rangestep, `bins` gates;
//   - values: raw 0 -> kNoEcho (Rainbow writes 0 for a bin that failed the slice's thresholds:
//     measured, nothing detected; the format has no separate "not measured" code inside a ray),
//     else min + (raw - 1) (max - min) / (2^depth - 2) (raw 1 is min, the top raw value is max);
//     8- and 16-bit data (big-endian);
//   - fields: the rawdata types (dBZ, dBuZ, V, W, ZDR, PhiDP, uPhiDP, KDP, RhoHV, ...), with units
//     and CF standard names for the corrected moments (dBZ, V, W, ZDR, PhiDP, KDP, RhoHV); a slice
//     lacking the loaded type gets kNoData gates;
//   - time: the scan's date and time (UTC); Nyquist: the V field's max when the file has V.
// Not read: pixmap products (<product>), point mode (type poi), flag BLOBs (depth < 8), ray time
// stamps. Every BLOB size is checked against rays x bins before it is inflated.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <cstddef>
#include <string>
#include <vector>

namespace atmoglobe::volume {

/// Reads a Rainbow 5 volume file (a gzip/bzip2 wrapper is unwrapped in memory).
Result<RadarVolume> readRainbow5(const std::string& path, const ReadOptions& options);
/// The same on the file's bytes; `label` names it in messages and becomes sourcePath.
Result<RadarVolume> readRainbow5(const std::string& label, const std::vector<unsigned char>& bytes,
                                 const ReadOptions& options);

/// True when `bytes` start (after blanks) with "<volume" (a Rainbow 5 volume).
bool looksLikeRainbow5(const unsigned char* bytes, std::size_t size);

}  // namespace atmoglobe::volume
