#pragma once
// CfRadial 1.x reader (netCDF classic and netCDF-4) through netCDF-C.
//
// What it reads: dimensions time (rays), range (gates), sweep; sweep_start_ray_index /
// sweep_end_ray_index (0-based, inclusive), fixed_angle, sweep_mode; azimuth(time),
// elevation(time); range(range) in m (gate centres); latitude/longitude/altitude (scalar or
// per ray: the first ray of the first sweep is used); fields are the numeric variables with
// dimensions (time, range).
//
// Choices (documented because files differ):
//  - Rays outside every sweep's [start, end] range (antenna transitions) are dropped.
//  - Per-ray azimuths are kept as the file gives them (normalised to [0, 360)); 358-361
//    rays a sweep are fine. A ray inside a sweep whose azimuth or elevation is NaN or the
//    variable's _FillValue is an error: the gates cannot be placed.
//  - Gate spacing is (range[n-1] - range[0]) / (n - 1); a range whose steps differ from it
//    by more than 1 % (or 0.5 m) is an error (non-uniform gates are not modelled).
//  - Values: raw * scale_factor + add_offset; raw equal to _FillValue or missing_value, or
//    NaN, -> kNoData. CfRadial has no "measured, nothing there" code, so kNoEcho never
//    appears: below-threshold gates are whatever the writer stored (usually the fill value).
//  - sweep_mode "rhi" (or "manual_rhi") -> Rhi; "azimuth_surveillance", "sector",
//    "manual_ppi", "ppi" -> Ppi; other text -> Other. Without sweep_mode the mode is Rhi
//    when the sweep's elevations span more than its azimuths, else Ppi.
//  - The antenna altitude is taken as above mean sea level (CfRadial: "altitude ... above
//    mean sea level").
//  - Not supported (an error says so): ragged rays (n_points / ray_n_gates), CfRadial 2
//    (one group per sweep).
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <string>

namespace atmoglobe::io {
class NetcdfFile;  // io/NetcdfFile.h
}

namespace atmoglobe::volume {

/// Reads a CfRadial 1.x file. Only options.fieldName (or the default reflectivity field)
/// is decoded, and nothing when options.loadValues is false.
Result<RadarVolume> readCfRadial(const std::string& path, const ReadOptions& options);
/// The same on a file already open (readRadarVolume opens HDF5 files once to detect and read).
Result<RadarVolume> readCfRadial(const io::NetcdfFile& file, const ReadOptions& options);

}  // namespace atmoglobe::volume
