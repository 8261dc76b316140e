#pragma once
// Station lists (radar sites, observation stations) for markers on the globe: CSV or JSON.
//
// CSV: a header row naming the columns, in any order, case-insensitive, surrounding blanks
// ignored; RFC 4180 quoting ("a, b" and "" for a quote inside quotes; a quoted field may not
// span lines). Recognised names:
//   id:        id, icao, station, station_id, site, site_id          (required)
//   latitude:  lat, latitude, lat_deg                                (required, degrees)
//   longitude: lon, long, longitude, lng, lon_deg                    (required, degrees)
//   elevation: elev, elevation, elevation_m, altitude, alt, height   (optional, m above MSL)
//   tower:     tower, tower_height, tower_height_m                   (optional, m)
//   name:      name, site_name, station_name                         (optional)
// When both an elevation-like column and `height` are present (the OURadar layout), `height`
// is the tower height. Other columns are ignored. Blank lines and lines starting with '#'
// are skipped; a UTF-8 byte-order mark and CRLF line ends are accepted.
//
// JSON: either an array of objects with the keys above, or an object mapping id -> object (the
// layout of nexrad-locations.json in github.com/OURadar/radar-data: "KTLX": {"latitude",
// "longitude", "elevation" (ground, m), "height" (tower, m), "wban"}). Numbers may be JSON
// numbers or numeric strings.
//
// Checks: latitude in [-90, 90]; longitude in [-360, 360] (normalised to [-180, 180]);
// elevation in [-1000, 10000] m and tower height in [0, 1000] m; all finite; id non-empty.
// Every error names the file, the line (CSV) or entry (JSON: id or array index) and the reason.
// Files over 64 MiB are refused (bounded memory).
#include <atmoglobe/globe/Result.h>

#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::volume {

struct Station {
  std::string id;
  double latDeg = 0.0;                      ///< WGS84 latitude (degrees)
  double lonDeg = 0.0;                      ///< longitude (degrees, [-180, 180])
  double elevationMeters = 0.0;             ///< ground elevation above mean sea level (m); 0 if not given
  std::string name;                         ///< free text; empty if not given
  bool hasElevation = false;                ///< the file gave an elevation
  std::optional<double> towerHeightMeters;  ///< antenna tower height above ground (m), if given
};

/// Reads a CSV or JSON station list (format from the first non-blank character: '[' or '{'
/// is JSON, anything else CSV). Stations are returned in file order (JSON objects: key order
/// as in the file). An empty list (header only, `[]`, `{}`) is not an error.
Result<std::vector<Station>> readStationList(const std::string& path);

/// The same from text already in memory; `sourceName` is used in messages in place of a path.
Result<std::vector<Station>> parseStationList(const std::string& text, const std::string& sourceName);

/// How messages name the built-in table.
inline constexpr const char* kBuiltinNexradSiteTable = "the built-in NEXRAD site table (assets/nexrad_sites.csv)";
/// The WSR-88D sites built into the library (assets/nexrad_sites.csv: ICAO id, name, position,
/// ground elevation and tower height; public-domain NOAA facts), parsed once: what legacy Level II
/// files, `synth --sites` and fly-to use when the user gives no list ($ATMOGLOBE_NEXRAD_SITES or
/// --nexrad-sites, which override it).
const std::vector<Station>& builtinNexradSites();
/// The station of `id` (any case) in `stations`; nullptr if none.
const Station* findStation(const std::vector<Station>& stations, const std::string& id);

}  // namespace atmoglobe::volume
