#pragma once
// ODIM_H5 polar volume (PVOL) and single scan (SCAN) reader, through netCDF-C's
// netCDF-4/HDF5 layer (groups /what /where /how /datasetN/{what,where,how,dataM}).
//
// What it reads (ODIM_H5 2.x): /where lat, lon (deg), height (m above mean sea level);
// /what object (PVOL or SCAN), date, time, source; per datasetN/where elangle (deg), nbins,
// nrays, rstart (km, the START of the first bin), rscale (m), a1gate; per dataM/what
// quantity, gain, offset, nodata, undetect (looked up in dataM/what, then datasetN/what,
// then /what, as ODIM lets attributes be inherited). Attributes stored as 1-element arrays
// are accepted.
//
// Geometry:
//  - firstGateRangeMeters = rstart * 1000 + rscale / 2 (centre of the first bin).
//  - Ray azimuths: rays are stored clockwise from north; a1gate only says which ray was
//    radiated first and does not change the order. If datasetN/how has startazA and
//    stopazA (nrays values each) each ray's azimuth is their midpoint (wrap at 360
//    handled). Otherwise ray i is centred at astart + (i + 0.5) * 360 / nrays, astart
//    (datasetN/how, ODIM 2.2: offset of the first ray's start, default 0) in degrees.
//  - Ray elevations: datasetN/how/elangles (nrays values) if present, else elangle.
//  - Bin count and size come from each dataset: they may differ between sweeps.
//  - Sweeps are sorted by elevation (stable), mode Ppi.
// Values: value = gain * raw + offset; raw == nodata -> kNoData, raw == undetect ->
// kNoEcho. When nodata == undetect (some converters write both 0) the file cannot tell
// them apart and the gate is reported kNoData (we do not claim a measurement).
// A sweep that lacks the requested quantity gets all gates kNoData.
// The data array's shape must be (nrays, nbins) exactly as the attributes say.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <string>

namespace atmoglobe::io {
class NetcdfFile;  // io/NetcdfFile.h
}

namespace atmoglobe::volume {

/// Reads an ODIM_H5 PVOL or SCAN file. Only options.fieldName (an ODIM quantity such as
/// DBZH; default: see chooseDefaultField) is decoded, nothing when options.loadValues is false.
Result<RadarVolume> readOdimH5(const std::string& path, const ReadOptions& options);
/// The same on a file already open (readRadarVolume opens HDF5 files once to detect and read).
Result<RadarVolume> readOdimH5(const io::NetcdfFile& file, const ReadOptions& options);

/// Units of an ODIM quantity (ODIM_H5 2.x table of quantities), empty if not known.
std::string odimQuantityUnits(const std::string& quantity);

}  // namespace atmoglobe::volume
