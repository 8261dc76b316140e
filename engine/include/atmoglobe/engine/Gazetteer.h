#pragma once
// Names to fly to, GL-free: the scene's radars and markers, the NEXRAD sites
// of a station list ($ATMOGLOBE_NEXRAD_SITES, the list the NEXRAD reader uses), places from the
// tz database's zone1970.tab (Debian tzdata: the principal city of each time zone, with its
// coordinates), and "LAT,LON" typed in.
//
// find(): "LAT,LON" (degrees, with an optional ",HEIGHT" in m) first; then names compared
// case-insensitively with '_' as a blank, in this order: an exact name or id, then a name that
// starts with the query, then one that contains it. Within a rank the source added first wins
// (the viewer adds the scene's radars, its markers, the NEXRAD list, then the gazetteer), so
// "KTLX" in a scene is the scene's radar, not the list's.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/StationList.h>

#include <string>
#include <vector>

namespace atmoglobe::engine {

struct Place {
  std::vector<std::string> names;  ///< the first is shown; all are matched
  std::string kind;                ///< "radar", "marker", "NEXRAD site", "place", "position"
  double latDeg = 0.0;
  double lonDeg = 0.0;
  double viewHeightMeters = 3e5;  ///< height to look from
};

class Gazetteer {
 public:
  void add(Place place);
  /// A station list (volume/StationList.h: CSV or JSON); each station by id and name.
  Status addStationList(const std::string& path, const std::string& kind, double viewHeightMeters);
  /// Stations already read (volume::builtinNexradSites), each by id and name.
  void addStations(const std::vector<volume::Station>& stations, const std::string& kind, double viewHeightMeters);
  /// zone1970.tab: "CODES<TAB>+DDMM[SS]+DDDMM[SS]<TAB>Area/City[/Sub]..."; each zone by its city
  /// ("New York") and its full name ("America/New_York").
  Status addZoneTab(const std::string& path, double viewHeightMeters);
  Status addZoneTabText(const std::string& text, const std::string& sourceName, double viewHeightMeters);

  /// The place for `query` (see the header comment), or an error naming the query and what is known.
  Result<Place> find(const std::string& query) const;
  std::size_t size() const { return places_.size(); }

 private:
  std::vector<Place> places_;
};

/// The default gazetteer file of Debian's tzdata.
inline constexpr const char* kZoneTabPath = "/usr/share/zoneinfo/zone1970.tab";

/// The pose to fly to for `place`: above it looking straight down with north up.
CameraPose viewOfPlace(const Place& place);

}  // namespace atmoglobe::engine
