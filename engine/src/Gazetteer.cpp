#include <atmoglobe/engine/Gazetteer.h>
#include <atmoglobe/globe/Text.h>
#include <atmoglobe/volume/StationList.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

namespace atmoglobe::engine {

namespace {

std::string normalised(const std::string& s) {
  std::string out = toLowerAscii(s);
  std::replace(out.begin(), out.end(), '_', ' ');
  return std::string(trimAscii(out));
}

/// "+DDMM" / "+DDDMMSS" style: `degreeDigits` digits of degrees, then minutes, then optional seconds.
bool parseIsoCoordinate(const std::string& s, std::size_t degreeDigits, double* deg) {
  if (s.size() != 1 + degreeDigits + 2 && s.size() != 1 + degreeDigits + 4) return false;
  if (s[0] != '+' && s[0] != '-') return false;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
  const double d = std::stod(s.substr(1, degreeDigits));
  const double m = std::stod(s.substr(1 + degreeDigits, 2));
  const double sec = s.size() > 1 + degreeDigits + 2 ? std::stod(s.substr(3 + degreeDigits, 2)) : 0.0;
  if (m >= 60.0 || sec >= 60.0) return false;
  *deg = (s[0] == '-' ? -1.0 : 1.0) * (d + m / 60.0 + sec / 3600.0);
  return true;
}

/// "LAT,LON[,HEIGHT]" with finite numbers in range; false when the text is not of that form.
bool parseLatLon(const std::string& text, Place* place, std::string* error) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    const std::string t(trimAscii(part));
    if (t.empty()) return false;
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(t, &used);
    } catch (...) {
      return false;
    }
    if (used != t.size()) return false;
    v.push_back(x);
  }
  if (v.size() != 2 && v.size() != 3) return false;
  for (double x : v)
    if (!std::isfinite(x)) {
      *error = "'" + text + "': not finite numbers";
      return true;
    }
  if (std::abs(v[0]) > 90.0 || std::abs(v[1]) > 360.0) {
    *error = "'" + text + "': latitude must be in [-90, 90] and longitude in [-360, 360] degrees";
    return true;
  }
  if (v.size() == 3 && !(v[2] >= 1.0 && v[2] <= 1e8)) {
    *error = "'" + text + "': the height must be in [1, 1e8] m";
    return true;
  }
  place->names = {text};
  place->kind = "position";
  place->latDeg = v[0];
  place->lonDeg = v[1] > 180.0 ? v[1] - 360.0 : (v[1] < -180.0 ? v[1] + 360.0 : v[1]);
  if (v.size() == 3) place->viewHeightMeters = v[2];
  return true;
}

}  // namespace

void Gazetteer::add(Place place) { places_.push_back(std::move(place)); }

Status Gazetteer::addStationList(const std::string& path, const std::string& kind, double viewHeightMeters) {
  auto stations = volume::readStationList(path);
  if (!stations) return stations.forwardError();
  addStations(*stations, kind, viewHeightMeters);
  return Ok{};
}

void Gazetteer::addStations(const std::vector<volume::Station>& stations, const std::string& kind,
                            double viewHeightMeters) {
  for (const volume::Station& s : stations) {
    Place p;
    p.names.push_back(s.id);
    if (!s.name.empty()) p.names.push_back(s.name);
    p.kind = kind;
    p.latDeg = s.latDeg;
    p.lonDeg = s.lonDeg;
    p.viewHeightMeters = viewHeightMeters;
    add(std::move(p));
  }
}

Status Gazetteer::addZoneTab(const std::string& path, double viewHeightMeters) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  return addZoneTabText(text.str(), path, viewHeightMeters);
}

Status Gazetteer::addZoneTabText(const std::string& text, const std::string& sourceName, double viewHeightMeters) {
  std::stringstream in(text);
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> columns;
    std::stringstream cols(line);
    std::string c;
    while (std::getline(cols, c, '\t')) columns.push_back(c);
    const std::string where = sourceName + " line " + std::to_string(lineNumber) + ": ";
    if (columns.size() < 3) return makeError(where + "expected country codes, coordinates and a zone name");
    const std::string& coords = columns[1];
    const std::size_t split = coords.find_first_of("+-", 1);
    double lat = 0.0, lon = 0.0;
    if (split == std::string::npos || !parseIsoCoordinate(coords.substr(0, split), 2, &lat) ||
        !parseIsoCoordinate(coords.substr(split), 3, &lon) || std::abs(lat) > 90.0 || std::abs(lon) > 180.0) {
      return makeError(where + "coordinates '" + coords + "' are not +-DDMM[SS]+-DDDMM[SS]");
    }
    const std::string& zone = columns[2];
    Place p;
    p.names.push_back(zone.substr(zone.find_last_of('/') + 1));
    p.names.push_back(zone);
    p.kind = "place";
    p.latDeg = lat;
    p.lonDeg = lon;
    p.viewHeightMeters = viewHeightMeters;
    add(std::move(p));
  }
  return Ok{};
}

Result<Place> Gazetteer::find(const std::string& query) const {
  Place position;
  std::string error;
  if (parseLatLon(query, &position, &error)) {
    if (!error.empty()) return makeError("fly to " + error);
    return position;
  }
  const std::string q = normalised(query);
  if (q.empty()) return makeError("fly to: give a radar, station or place name, or LAT,LON");
  // Rank 0: exact, 1: prefix, 2: substring; the first place of the best rank wins.
  const Place* best = nullptr;
  int bestRank = 3;
  for (const Place& p : places_) {
    for (const std::string& name : p.names) {
      const std::string n = normalised(name);
      const std::size_t at = n.find(q);
      const int rank = n == q ? 0 : at == 0 ? 1 : at != std::string::npos ? 2 : 3;
      if (rank < bestRank) {
        bestRank = rank;
        best = &p;
      }
    }
    if (bestRank == 0) break;
  }
  if (!best) {
    return makeError("fly to '" + query + "': no radar, station or place of that name (" +
                     std::to_string(places_.size()) + " known), and not LAT,LON");
  }
  return *best;
}

CameraPose viewOfPlace(const Place& place) {
  CameraPose pose;
  pose.latDeg = place.latDeg;
  pose.lonDeg = place.lonDeg;
  pose.heightMeters = place.viewHeightMeters;
  pose.headingDeg = 0.0;
  pose.pitchDeg = -90.0;
  pose.rollDeg = 0.0;
  return pose;
}

}  // namespace atmoglobe::engine
