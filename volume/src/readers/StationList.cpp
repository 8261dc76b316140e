#include <atmoglobe/volume/StationList.h>

#include <atmoglobe/globe/Text.h>

#include <nlohmann/json.hpp>

#include <optional>
#include <string_view>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace atmoglobe::volume {

// Generated from assets/nexrad_sites.csv (volume/CMakeLists.txt).
std::optional<std::string_view> embeddedVolumeAsset(std::string_view fileName);

namespace {

constexpr std::uintmax_t kMaxFileBytes = 64ull << 20;

enum class Column { Id, Lat, Lon, Elevation, Height, Tower, Name, Other };

// `height` is kept apart: it is the elevation unless an elevation-like column/key also exists.
Column columnFor(const std::string& rawName) {
  const std::string n = toLowerAscii(trimAscii(rawName));
  if (n == "id" || n == "icao" || n == "station" || n == "station_id" || n == "site" || n == "site_id")
    return Column::Id;
  if (n == "lat" || n == "latitude" || n == "lat_deg") return Column::Lat;
  if (n == "lon" || n == "long" || n == "longitude" || n == "lng" || n == "lon_deg") return Column::Lon;
  if (n == "elev" || n == "elevation" || n == "elevation_m" || n == "altitude" || n == "alt") return Column::Elevation;
  if (n == "height") return Column::Height;
  if (n == "tower" || n == "tower_height" || n == "tower_height_m") return Column::Tower;
  if (n == "name" || n == "site_name" || n == "station_name") return Column::Name;
  return Column::Other;
}

const char* columnLabel(Column c) {
  switch (c) {
    case Column::Lat: return "latitude";
    case Column::Lon: return "longitude";
    case Column::Elevation: return "elevation";
    case Column::Height: return "height";
    case Column::Tower: return "tower height";
    default: return "value";
  }
}

// Parses a whole field as a finite double ("35.5", " -97 ", "1e3"); nullopt otherwise.
std::optional<double> parseNumber(const std::string& field) {
  const std::string t(trimAscii(field));
  if (t.empty()) return std::nullopt;
  const char* b = t.data();
  const char* e = b + t.size();
  if (*b == '+') ++b;  // from_chars does not take a leading '+'
  double v = 0;
  const auto [ptr, ec] = std::from_chars(b, e, v);
  if (ec != std::errc() || ptr != e || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string shortText(const std::string& s) {
  std::string t = s.size() > 40 ? s.substr(0, 40) + "..." : s;
  return "'" + t + "'";
}

std::string numberText(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// Range checks on one station; `where` is "line 7" or "entry 'KTLX'".
std::optional<std::string> checkStation(Station& s) {
  if (s.id.empty()) return std::string("empty id");
  if (!(s.latDeg >= -90.0 && s.latDeg <= 90.0))
    return "bad latitude " + numberText(s.latDeg) + " (must be in [-90, 90])";
  if (!(s.lonDeg >= -360.0 && s.lonDeg <= 360.0))
    return "bad longitude " + numberText(s.lonDeg) + " (must be in [-360, 360])";
  s.lonDeg = std::remainder(s.lonDeg, 360.0);
  if (s.lonDeg == -180.0) s.lonDeg = 180.0;
  if (!(s.elevationMeters >= -1000.0 && s.elevationMeters <= 10000.0))
    return "bad elevation " + numberText(s.elevationMeters) + " m (must be in [-1000, 10000])";
  if (s.towerHeightMeters && !(*s.towerHeightMeters >= 0.0 && *s.towerHeightMeters <= 1000.0))
    return "bad tower height " + numberText(*s.towerHeightMeters) + " m (must be in [0, 1000])";
  return std::nullopt;
}

// --- CSV ---

// Splits one line into fields (RFC 4180 quoting). Returns an error text on an unterminated
// quote or text after a closing quote.
std::optional<std::string> splitCsv(const std::string& line, std::vector<std::string>* out) {
  out->clear();
  std::string field;
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (true) {
    field.clear();
    // Leading blanks before a quote are allowed ( , "x").
    std::size_t j = i;
    while (j < n && (line[j] == ' ' || line[j] == '\t')) ++j;
    if (j < n && line[j] == '"') {
      i = j + 1;
      bool closed = false;
      while (i < n) {
        if (line[i] == '"') {
          if (i + 1 < n && line[i + 1] == '"') {
            field.push_back('"');
            i += 2;
          } else {
            closed = true;
            ++i;
            break;
          }
        } else {
          field.push_back(line[i++]);
        }
      }
      if (!closed) return std::string("unterminated quoted field (quoted fields may not span lines)");
      while (i < n && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i < n && line[i] != ',') return std::string("text after a closing quote");
    } else {
      while (i < n && line[i] != ',') field.push_back(line[i++]);
    }
    out->push_back(field);
    if (i >= n) break;
    ++i;  // the comma
  }
  return std::nullopt;
}

Result<std::vector<Station>> parseCsv(const std::string& text, const std::string& src) {
  std::vector<Station> stations;
  std::vector<std::string> fields;
  bool haveHeader = false;
  std::size_t lineNo = 0, pos = 0;
  int colId = -1, colLat = -1, colLon = -1, colElev = -1, colHeight = -1, colTower = -1, colName = -1;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string_view t = trimAscii(line);
    if (t.empty() || t[0] == '#') continue;
    const std::string where = src + ": line " + std::to_string(lineNo) + ": ";
    if (auto err = splitCsv(line, &fields)) return makeError(where + *err);
    if (!haveHeader) {
      haveHeader = true;
      for (std::size_t k = 0; k < fields.size(); ++k) {
        const Column c = columnFor(fields[k]);
        int* slot = c == Column::Id          ? &colId
                    : c == Column::Lat       ? &colLat
                    : c == Column::Lon       ? &colLon
                    : c == Column::Elevation ? &colElev
                    : c == Column::Height    ? &colHeight
                    : c == Column::Tower     ? &colTower
                    : c == Column::Name      ? &colName
                                             : nullptr;
        if (!slot) continue;
        if (*slot >= 0)
          return makeError(where + "header names two columns for the same thing: " +
                           shortText(fields[static_cast<std::size_t>(*slot)]) + " and " + shortText(fields[k]));
        *slot = static_cast<int>(k);
      }
      std::string missing;
      if (colId < 0) missing += " id (id/icao/station)";
      if (colLat < 0) missing += " latitude (lat/latitude)";
      if (colLon < 0) missing += " longitude (lon/long/longitude)";
      if (!missing.empty())
        return makeError(where + "header lacks the column(s):" + missing + "; the first row must name the columns");
      // `height` is the elevation unless an elevation column exists, then it is the tower height.
      if (colHeight >= 0) {
        if (colElev < 0) colElev = colHeight;
        else if (colTower < 0) colTower = colHeight;
      }
      continue;
    }
    const int needed = std::max({colId, colLat, colLon, colElev, colTower, colName});
    if (static_cast<int>(fields.size()) <= needed)
      return makeError(where + "has " + std::to_string(fields.size()) + " fields, the header needs at least " +
                       std::to_string(needed + 1));
    Station s;
    s.id = trimAscii(fields[static_cast<std::size_t>(colId)]);
    auto number = [&](int col, Column what, double* dst) -> std::optional<std::string> {
      const auto v = parseNumber(fields[static_cast<std::size_t>(col)]);
      if (!v)
        return std::string(columnLabel(what)) + " " + shortText(fields[static_cast<std::size_t>(col)]) +
               " is not a number";
      *dst = *v;
      return std::nullopt;
    };
    if (auto e = number(colLat, Column::Lat, &s.latDeg)) return makeError(where + *e);
    if (auto e = number(colLon, Column::Lon, &s.lonDeg)) return makeError(where + *e);
    if (colElev >= 0 && !trimAscii(fields[static_cast<std::size_t>(colElev)]).empty()) {  // empty cell: unknown
      if (auto e = number(colElev, Column::Elevation, &s.elevationMeters)) return makeError(where + *e);
      s.hasElevation = true;
    }
    if (colTower >= 0 && !trimAscii(fields[static_cast<std::size_t>(colTower)]).empty()) {
      double h = 0;
      if (auto e = number(colTower, Column::Tower, &h)) return makeError(where + *e);
      s.towerHeightMeters = h;
    }
    if (colName >= 0) s.name = trimAscii(fields[static_cast<std::size_t>(colName)]);
    if (auto e = checkStation(s)) return makeError(where + "station " + shortText(s.id) + ": " + *e);
    stations.push_back(std::move(s));
  }
  if (!haveHeader) return makeError(src + ": no header row (expected columns such as id,lat,lon,elevation)");
  return stations;
}

// --- JSON ---

using Json = nlohmann::ordered_json;

// A number from a JSON number or a numeric string.
std::optional<double> jsonNumber(const Json& v) {
  if (v.is_number()) {
    const double d = v.get<double>();
    return std::isfinite(d) ? std::optional<double>(d) : std::nullopt;
  }
  if (v.is_string()) return parseNumber(v.get<std::string>());
  return std::nullopt;
}

std::string jsonText(const Json& v) {
  std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 40) + "..." : s;
}

// One station object; `id` from the key (object form) or from the object's own id key.
std::optional<std::string> stationFromJson(const Json& obj, std::string id, Station* out) {
  if (!obj.is_object()) return "is " + std::string(obj.type_name()) + ", not an object";
  const Json* lat = nullptr;
  const Json* lon = nullptr;
  const Json* elev = nullptr;
  const Json* height = nullptr;
  const Json* tower = nullptr;
  const Json* name = nullptr;
  const Json* idValue = nullptr;
  for (const auto& [key, value] : obj.items()) {
    switch (columnFor(key)) {
      case Column::Id:
        if (!idValue) idValue = &value;
        break;
      case Column::Lat:
        if (!lat) lat = &value;
        break;
      case Column::Lon:
        if (!lon) lon = &value;
        break;
      case Column::Elevation:
        if (!elev) elev = &value;
        break;
      case Column::Height: height = &value; break;
      case Column::Tower:
        if (!tower) tower = &value;
        break;
      case Column::Name:
        if (!name) name = &value;
        break;
      case Column::Other: break;
    }
  }
  if (height) {
    if (!elev) elev = height;
    else if (!tower) tower = height;
  }
  if (id.empty() && idValue) {
    if (idValue->is_string()) id = idValue->get<std::string>();
    else if (idValue->is_number_integer()) id = idValue->dump();
    else return "id " + jsonText(*idValue) + " is not text";
  }
  Station s;
  s.id = trimAscii(id);
  if (s.id.empty()) return std::string("has no id (id/icao/station)");
  if (!lat) return std::string("has no latitude (lat/latitude)");
  if (!lon) return std::string("has no longitude (lon/long/longitude)");
  const auto la = jsonNumber(*lat), lo = jsonNumber(*lon);
  if (!la) return "latitude " + jsonText(*lat) + " is not a number";
  if (!lo) return "longitude " + jsonText(*lon) + " is not a number";
  s.latDeg = *la;
  s.lonDeg = *lo;
  if (elev && !elev->is_null()) {
    const auto e = jsonNumber(*elev);
    if (!e) return "elevation " + jsonText(*elev) + " is not a number";
    s.elevationMeters = *e;
    s.hasElevation = true;
  }
  if (tower && !tower->is_null()) {
    const auto t = jsonNumber(*tower);
    if (!t) return "tower height " + jsonText(*tower) + " is not a number";
    s.towerHeightMeters = *t;
  }
  if (name && name->is_string()) s.name = name->get<std::string>();
  if (auto e = checkStation(s)) return e;
  *out = std::move(s);
  return std::nullopt;
}

Result<std::vector<Station>> parseJson(const std::string& text, const std::string& src) {
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::exception& e) {
    return makeError(src + ": not valid JSON: " + e.what());
  }
  std::vector<Station> stations;
  if (root.is_array()) {
    for (std::size_t i = 0; i < root.size(); ++i) {
      Station s;
      if (auto e = stationFromJson(root[i], "", &s)) {
        const Json& item = root[i];
        std::string label = "entry " + std::to_string(i);
        if (item.is_object()) {
          for (const auto& [key, value] : item.items())
            if (columnFor(key) == Column::Id && value.is_string()) {
              label += " ('" + value.get<std::string>() + "')";
              break;
            }
        }
        return makeError(src + ": " + label + ": " + *e);
      }
      stations.push_back(std::move(s));
    }
  } else if (root.is_object()) {
    for (const auto& [key, value] : root.items()) {
      Station s;
      if (auto e = stationFromJson(value, key, &s)) return makeError(src + ": entry '" + key + "': " + *e);
      stations.push_back(std::move(s));
    }
  } else {
    return makeError(src + ": JSON must be an array of station objects or an object mapping id -> station, not " +
                     std::string(root.type_name()));
  }
  return stations;
}

}  // namespace

Result<std::vector<Station>> parseStationList(const std::string& text, const std::string& sourceName) {
  std::size_t start = 0;
  if (text.size() >= 3 && std::memcmp(text.data(), "\xEF\xBB\xBF", 3) == 0) start = 3;  // UTF-8 BOM
  const std::string_view content = trimAscii(std::string_view(text).substr(start));
  if (content.empty()) return makeError(sourceName + ": the file is empty (expected CSV with a header row, or JSON)");
  const std::string body = text.substr(start);
  if (content.front() == '[' || content.front() == '{') return parseJson(body, sourceName);
  return parseCsv(body, sourceName);
}

Result<std::vector<Station>> readStationList(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open station list: " + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return makeError(path + ": cannot read station list (not a regular file?)");
  if (static_cast<std::uintmax_t>(size) > kMaxFileBytes)
    return makeError(path + ": station list is " + std::to_string(size) + " bytes; more than the 64 MiB accepted");
  in.seekg(0, std::ios::beg);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in.read(text.data(), size)) return makeError(path + ": cannot read station list");
  return parseStationList(text, path);
}

const std::vector<Station>& builtinNexradSites() {
  // The table is part of the build (a broken one fails StationList.BuiltinNexradTable*): an
  // unreadable one is empty here rather than an exception in every reader.
  static const std::vector<Station> kSites = [] {
    const auto text = embeddedVolumeAsset("nexrad_sites.csv");
    if (!text) return std::vector<Station>{};
    auto parsed = parseStationList(std::string(*text), kBuiltinNexradSiteTable);
    return parsed ? std::move(*parsed) : std::vector<Station>{};
  }();
  return kSites;
}

const Station* findStation(const std::vector<Station>& stations, const std::string& id) {
  for (const Station& s : stations)
    if (equalsIgnoringCaseAscii(s.id, id)) return &s;
  return nullptr;
}

}  // namespace atmoglobe::volume
