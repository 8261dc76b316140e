#pragma once
// Radar file entry point: detect the format from the file's content and read it.
//
// Formats: CfRadial 1.x (netCDF classic or netCDF-4), ODIM_H5 PVOL/SCAN (HDF5, read through
// netCDF-C), NEXRAD Level II Archive II, Sigmet/IRIS RAW, Rainbow 5 volumes; each of them also
// gzip- or bzip2-wrapped (io/Compression.h: unwrapped in memory, the format detected from the
// content, messages "FILE (gzip): ..."). The file name is never used to decide.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <string>
#include <vector>

namespace atmoglobe::volume {

enum class RadarFormat { Unknown, CfRadial, OdimH5, NexradLevel2, SigmetIris, Rainbow5 };
const char* toString(RadarFormat f);

/// Detects the format from the file's content:
///   "CDF\x01" / "CDF\x02" / "CDF\x05" at offset 0 (classic netCDF)      -> CfRadial
///   HDF5 signature "\x89HDF\r\n\x1a\n" at offset 0, 512, 1024, 2048 ...  -> opened with
///     netCDF-C: root attribute Conventions starting "ODIM_H5", or a /what group with an
///     `object` attribute -> OdimH5; Conventions mentioning CF/Radial or CF-Radial (also in
///     the `version` attribute), or a root variable sweep_start_ray_index -> CfRadial
///   "AR2V" or "ARCHIVE2" (legacy) at offset 0                            -> NexradLevel2
///   IRIS product_hdr (id 27) of a RAW product (type 15) at offset 0      -> SigmetIris
///   "<volume" at offset 0 (after blanks)                                 -> Rainbow5
///   gzip (1f 8b) or bzip2 ("BZh1".."BZh9") at offset 0                   -> the format of the
///     decompressed content, by the rules above
/// Anything else (including a readable HDF5/netCDF file with neither mark) -> Unknown.
/// Errors: the file cannot be opened or read.
Result<RadarFormat> detectRadarFormat(const std::string& path);

/// Detects the format and reads the file with the matching reader. Unknown formats are an
/// error naming the file and its first bytes. A compressed file is read from memory;
/// RadarVolume::compression says which wrapper it had.
Result<RadarVolume> readRadarVolume(const std::string& path, const ReadOptions& options);

/// Picks the field decoded when ReadOptions::fieldName is empty: the reflectivity field by
/// meaning (CF standard_name, units dBZ, known names in any case; FieldKind.h,
/// chooseDefaultFieldWithReason), else the first field. Empty if there are no fields.
std::string chooseDefaultField(const std::vector<FieldInfo>& fields);

/// Index in `fields` of the field to load: `requested`, or chooseDefaultField when it is
/// empty. Precondition: `fields` not empty. The error (without the file name) lists the
/// fields the file has: "no <noun> 'X' (the file has: A, B)".
Result<std::size_t> selectField(const std::vector<FieldInfo>& fields, const std::string& requested,
                                const std::string& noun = "field");

/// Normalises a date-time text to "YYYY-MM-DDTHH:MM:SSZ" (accepts a space or 'T' between
/// date and time, drops fractional seconds). Returns an empty string if it does not parse.
std::string normalizeIso8601(const std::string& text);

/// Seconds since 1970-01-01T00:00:00Z of a date-time normalizeIso8601 accepts; NaN if it does not.
double iso8601ToEpochSeconds(const std::string& text);

/// The volume's metadata as one JSON object (for `atmoglobe info --json`): format, file,
/// compression ("gzip"/"bzip2", only for a wrapped file),
/// site {name, lat_deg, lon_deg, height_m, height_datum[, location_source]}, files (when
/// assembled from several), time, beam_width_deg, sweeps[] {index, index_in_file,
/// fixed_angle_deg, fixed_angle_kind, mode, rays, gates, first_gate_m, gate_spacing_m, complete
/// [, start_time, end_time]}, fields[] {name, units, ...}, loaded_field, warnings[].
std::string describeVolumeJson(const RadarVolume& v);
/// The same as human-readable text, one sweep per line ("partial" after an incomplete one), then
/// one "warning: ..." line per warning.
std::string describeVolumeText(const RadarVolume& v);

}  // namespace atmoglobe::volume
