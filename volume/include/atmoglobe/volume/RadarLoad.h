#pragma once
// The one load path of a radar file for every tool that draws, exports or geolocates it
// (`render`, `view`, `export-cones`, `gates`, `bench`): read the file (format from its content,
// one field decoded), bring the antenna to the WGS84 ellipsoid (EGM96 geoid or not), and, when
// asked, build the render layout in the radar's own geometry (PolarVolume).
//
// GL-free: the GPU side (engine::RadarVolumeGL, its beam approximation) starts from the layout
// this returns. The beam model of the layout is volume::BeamModel{} (ke = 4/3, R = WGS84
// geocentric radius at the site), the model every renderer and the reference use.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <optional>
#include <string>

namespace atmoglobe::volume {

struct RadarLoadOptions {
  /// Field to decode; empty: the reflectivity field if the file has one (chooseDefaultField).
  std::string fieldName;
  /// Antenna heights given above mean sea level are brought to the ellipsoid with the EGM96
  /// undulation (resolveSite); false: the MSL height is used as ellipsoidal (`--no-geoid`).
  bool useGeoid = true;
  /// Also build the render layout (PolarVolume). Its values are a copy of the sweeps' values,
  /// so those are released from LoadedRadar::volume once the layout holds them: the data are
  /// held once (set keepSweepValues to keep both).
  bool buildRenderLayout = false;
  bool keepSweepValues = false;
  /// NEXRAD site list for legacy NEXRAD files (ReadOptions::nexradSiteList; empty:
  /// $ATMOGLOBE_NEXRAD_SITES).
  std::string nexradSiteList;
};

struct LoadedRadar {
  /// The file as read: site as the file gives it (name, datum), sweeps, ray angles, fields,
  /// the decoded field. Sweep values are empty when the layout was built without
  /// keepSweepValues.
  RadarVolume volume;
  /// The antenna on the WGS84 ellipsoid, the undulation applied and the datum note for users.
  /// The note also says where the position came from when not from the file (legacy NEXRAD:
  /// the site list), followed by one "\nwarning: ..." line per RadarVolume::warnings entry, so
  /// every tool that prints the note shows what the readers repaired or found missing.
  SiteResolution site;
  /// The render layout (only with buildRenderLayout).
  std::optional<PolarVolume> layout;
};

/// Reads `path` and prepares it as `options` say. `path` may name one file or a set of files of
/// one volume (a directory, a glob pattern, a comma-separated list: RadarVolumeSet.h,
/// isRadarFileSet), assembled by readRadarVolumeSet. Errors name the file and the problem: the
/// reader's (unreadable file, unknown format, no such field: "FILE: no field 'X' (the file has:
/// ...)"), the site's ("FILE: <what is wrong with the site>"), the layout's ("FILE: RHI volumes
/// cannot be volume-rendered yet; ...", "FILE: no PPI sweep ...").
Result<LoadedRadar> loadRadar(const std::string& path, const RadarLoadOptions& options);

}  // namespace atmoglobe::volume
