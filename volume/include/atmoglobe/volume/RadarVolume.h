#pragma once
// The radar data model: a site, sweeps of rays of gates, and one loaded field.
//
// GL-free. Readers (CfRadial, ODIM_H5, NEXRAD Level II) fill it; geolocation and the
// renderers read it. Only the field that was asked for is decoded (see ReadOptions).
//
// Gate values are floats in the field's physical units with two distinct sentinels:
//   - "no data"  (not measured: outside the scan, not radiated, fill value) = quiet NaN
//   - "no echo"  (measured, nothing detected: ODIM undetect, NEXRAD raw 0)  = -infinity
// Use isNoData()/isNoEcho() rather than comparing.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace atmoglobe::volume {

inline constexpr float kNoData = std::numeric_limits<float>::quiet_NaN();
inline constexpr float kNoEcho = -std::numeric_limits<float>::infinity();
inline bool isNoData(float v) { return std::isnan(v); }
inline bool isNoEcho(float v) { return std::isinf(v) && v < 0; }
inline bool isMeasuredValue(float v) { return std::isfinite(v); }

/// Which vertical datum a height is given in.
enum class HeightDatum {
  MeanSeaLevel,  ///< above mean sea level (what radar files store)
  Ellipsoid,     ///< above the WGS84 ellipsoid
};
const char* toString(HeightDatum d);

struct RadarSite {
  std::string name;                  ///< site id or name as the file gives it (may be empty)
  double latDeg = 0.0;               ///< WGS84 latitude (degrees)
  double lonDeg = 0.0;               ///< WGS84 longitude (degrees)
  double antennaHeightMeters = 0.0;  ///< antenna (feedhorn) height in `heightDatum` (m)
  HeightDatum heightDatum = HeightDatum::MeanSeaLevel;
  /// Where the radar is, when the file (or the NEXRAD site list) says it apart from the name:
  /// ODIM's PLC ("Wideumont"), CfRadial's site_name beside its instrument_name, Rainbow's sensor
  /// name beside its id, the NEXRAD list's name of the ICAO id. Empty otherwise.
  std::string placeName;
};

/// How titles, `info` and slices name a site: "bewid (Wideumont)", or the name alone when there
/// is no place (or it is the name), or the place alone when there is no name.
std::string siteTitle(const RadarSite& site);

enum class SweepMode { Ppi, Rhi, Other };
const char* toString(SweepMode m);

/// One sweep (a PPI at a fixed elevation, or an RHI at a fixed azimuth).
struct Sweep {
  int indexInFile = 0;         ///< sweep/cut number in the file (0-based)
  double fixedAngleDeg = 0.0;  ///< elevation (PPI) or azimuth (RHI), degrees
  SweepMode mode = SweepMode::Ppi;
  std::vector<float> azimuthDeg;      ///< per ray, degrees clockwise from north [0, 360)
  std::vector<float> elevationDeg;    ///< per ray, degrees above horizontal
  double firstGateRangeMeters = 0.0;  ///< slant range of the CENTRE of the first gate (m)
  double gateSpacingMeters = 0.0;     ///< centre-to-centre spacing (m)
  std::uint32_t gateCount = 0;        ///< gates per ray for the loaded field
  /// Decoded values of the loaded field, ray-major: values[ray * gateCount + gate].
  /// Empty when no field was loaded (metadata-only read).
  std::vector<float> values;
  /// When the sweep was scanned (UTC, "YYYY-MM-DDTHH:MM:SSZ"), empty when the file does not say
  /// (ODIM datasetN/what start/end date and time; NEXRAD first and last radial).
  std::string startTimeIso8601, endTimeIso8601;
  /// false: the sweep was cut short (a NEXRAD volume in progress); its missing azimuths are
  /// no-data rays and RadarVolume::warnings says which.
  bool complete = true;

  std::size_t rayCount() const { return azimuthDeg.size(); }
  double gateRangeMeters(std::uint32_t gate) const { return firstGateRangeMeters + gate * gateSpacingMeters; }
  float value(std::size_t ray, std::uint32_t gate) const { return values[ray * gateCount + gate]; }
};

struct FieldInfo {
  std::string name;          ///< name in the file (DBZH, reflectivity, REF, ...)
  std::string units;         ///< e.g. "dBZ", "m/s"; empty if the file does not say
  std::string standardName;  ///< CF standard_name (CfRadial); empty if the file does not say
};

struct RadarVolume {
  std::string format;      ///< "CfRadial", "ODIM_H5", "NEXRAD Level II"
  std::string sourcePath;  ///< file it was read from
  /// "gzip" or "bzip2" when the file was a compressed wrapper around the format (io/Compression.h),
  /// empty for a plain file.
  std::string compression;
  RadarSite site;
  /// Where the site position comes from when not from the file itself (legacy NEXRAD Level II
  /// gives none: "NEXRAD site list FILE (KTLX: ...)"); empty: the file.
  std::string siteLocationSource;
  std::string timeIso8601;    ///< volume start time, UTC, e.g. "2016-06-01T15:00:25Z"
  double beamWidthDeg = 0.0;  ///< half-power beam width if known, else 0
  /// Largest Nyquist (unambiguous) velocity of the volume's sweeps (m/s), NaN if the file does
  /// not give one (CfRadial nyquist_velocity, ODIM how/NI, NEXRAD RAD block).
  double nyquistVelocityMps = std::numeric_limits<double>::quiet_NaN();
  std::vector<FieldInfo> fields;  ///< every field the file holds
  FieldInfo loadedField;          ///< the field decoded into Sweep::values (name empty if none)
  std::vector<Sweep> sweeps;      ///< sorted by fixed angle (stable: file order for equal angles)
  /// What the reader dropped, repaired or could not find (antenna-transition rays left out,
  /// duplicate rays dropped, split cuts without the field left out, sweeps stored out of
  /// order and sorted, missing elevations, incomplete cuts, files merged ...), one sentence
  /// each, for users (`info` prints them, `--json` lists them). Empty: the file was read as it is.
  std::vector<std::string> warnings;
  /// The files assembled into this volume when it came from several (RadarVolumeSet.h); empty
  /// when it is the one file `sourcePath`.
  std::vector<std::string> sourceFiles;
  /// The file holds one sweep of a volume cycle (ODIM object SCAN): volumes are assembled
  /// from such files by RadarVolumeSet.h.
  bool singleScanFile = false;
};

/// Sorts the sweeps by fixed angle (stable: file order for equal angles); when that changes their
/// order, adds a warning giving the stored order.
void sortSweepsByAngle(RadarVolume& volume);

struct ReadOptions {
  /// Field to decode. Empty: pick the reflectivity field if the file has one
  /// (DBZH, reflectivity*, REF, DBZ, TH ...), else the first field.
  std::string fieldName;
  /// false: read metadata only (site, sweeps, ray angles, fields), decode no values.
  bool loadValues = true;
  /// NEXRAD site list (CSV or JSON, StationList.h) giving the position of legacy NEXRAD Level II
  /// files, which carry only the ICAO id. Empty: $ATMOGLOBE_NEXRAD_SITES.
  std::string nexradSiteList;
};

}  // namespace atmoglobe::volume
