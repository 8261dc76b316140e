#pragma once
// Vaisala Sigmet/IRIS RAW product reader (the ingest data IRIS writes: one volume task per file).
//
// Layout (IRIS Programmer's Manual, "IRIS and RDA Programming Guide": product_hdr, ingest_header,
// raw_prod_bhdr, ingest_data_header; all little-endian): 6144-byte records. Record 0 holds the
// product_hdr (structure id 27, product type 15 = RAW), record 1 the ingest_header (id 23:
// ingest_configuration with the site, task_configuration with the DSP data mask, range, scan and
// misc info). Every later record starts with a 12-byte raw_prod_bhdr (record and sweep number);
// the first record of a sweep then holds one 76-byte ingest_data_header per data type in the mask
// (sweep start time, rays expected, fixed angle, bits per bin, type), and the rays follow as one
// stream of 16-bit words running across records: for each ray position, one run-length-compressed
// ray per data type in mask order. Code word c: bit 15 set -> (c & 0x7FFF) data words follow;
// c == 1 -> end of ray (a ray that starts with it is absent); otherwise c zero words. A ray
// expands to a 6-word header (azimuth and elevation at start and end as BIN2 angles, bins in the
// ray, seconds from the sweep start) and its bins (1 or 2 bytes each).
//
// What the reader makes of it:
//   - site: ingest_configuration latitude/longitude (BIN4 binary angles, 360/2^32 deg), antenna
//     height = altitude of the radar (cm above sea level), else ground height + radar height above
//     ground (m); HeightDatum::MeanSeaLevel; name = the IRIS site name;
//   - time: volume scan start time (ymds_time; milliseconds in the low 10 bits; when the UTC flag
//     (0x800) is clear the time is local standard time and the "minutes west of GMT" is added);
//   - sweeps: one per ingest_data_header set; fixed angle = its BIN2 fixed angle (elevation for a
//     PPI, azimuth for an RHI); mode from the task's antenna scan mode (1 PPI sector, 4 PPI
//     continuous -> Ppi; 2 RHI -> Rhi; manual and file scans -> Other);
//   - rays: the rays present (absent rays dropped), azimuth = circular midpoint of start and end,
//     elevation = midpoint of start and end (BIN2 angles above 180 deg are negative elevations);
//   - gates: task_range_info: first bin range (cm; the centre of the first bin, as Radx/LROSE read
//     it), output bin step (cm), number of output bins; variable bin spacing is refused;
//   - fields: the data types of the DSP mask with a published conversion, named as IRIS names them
//     without "DB_" (DBT2, DBZ2, VEL2, WIDTH2, ZDR2, KDP2, PHIDP2, RHOHV2, SQI2 ...), with units and
//     CF standard names for the corrected moments (so DBZ2, not the total power DBT2, is the
//     default reflectivity): 1-byte dBZ types (N-64)/2, VEL (N-128)/127 x Nyquist, WIDTH
//     N/256 x Nyquist, ZDR (N-128)/16, PHIDP 180(N-1)/254, RHOHV/SQI sqrt((N-1)/253), LDR
//     (N-1)/5-45; 2-byte dBZ/VEL/ZDR/KDP/LDR types (N-32768)/100, WIDTH2 N/100, RHOHV2/SQI2
//     (N-1)/65533, PHIDP2 360(N-1)/65534. Raw 0 (bin below the processor's thresholds) ->
//     kNoEcho; raw 255 / 65535 ("area not scanned") -> kNoData; bins past a ray's own bin count
//     and rays absent in the loaded type -> kNoData. Not decoded (not listed as fields): the
//     extended ray headers (DB_XHDR), hydrometeor classes, SNR, 1-byte KDP and other types
//     without a conversion here;
//   - Nyquist velocity = wavelength x PRF / 4 x (multi-PRF factor: 1, 2, 3, 4 for 1:1, 2:3, 3:4,
//     4:5), from task_misc_info and task_dsp_info.
// Every offset and count is checked against the file; errors name the file, record and sweep.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <cstddef>
#include <string>
#include <vector>

namespace atmoglobe::volume {

/// IRIS record size.
inline constexpr std::size_t kSigmetRecordBytes = 6144;

/// Reads a Sigmet/IRIS RAW file (a gzip/bzip2 wrapper is unwrapped in memory).
Result<RadarVolume> readSigmetIris(const std::string& path, const ReadOptions& options);
/// The same on the file's bytes; `label` names it in messages and becomes sourcePath.
Result<RadarVolume> readSigmetIris(const std::string& label, const std::vector<unsigned char>& bytes,
                                   const ReadOptions& options);

/// True when `bytes` start with an IRIS product_hdr of a RAW product (structure id 27 at byte 0,
/// product type code 15 at byte 24). Needs at least 26 bytes.
bool looksLikeSigmetRaw(const unsigned char* bytes, std::size_t size);

}  // namespace atmoglobe::volume
