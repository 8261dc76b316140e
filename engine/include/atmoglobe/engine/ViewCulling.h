#pragma once
// Load only what the view shows, GL-free.
//
// A radar volume lies inside a sphere about its antenna: every gate is on a beam whose path
// length is the gate's slant range, so no gate is farther from the antenna (in a straight line)
// than the last gate's range, plus half a gate and the beam's half-width there. With vertical
// exaggeration e > 1 heights above the ellipsoid grow e times, so the radius is scaled by e
// (conservative). A volume whose sphere lies wholly outside one frustum plane, or wholly behind
// the WGS84 ellipsoid seen from the eye (a horizon culling point in scaled space, Horizon.h), is
// not visible from that camera, and `render` does not load it (its file is only opened for the
// site and the range: a metadata read).
//
// The viewer defers such radars instead (deferRadarsOutsideView) and loads each when the moving
// camera first may see it.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/Decimate.h>
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <glm/glm.hpp>

#include <cstdint>

#include <string>
#include <vector>

namespace atmoglobe::engine {

/// false only if no point of the sphere can be seen from the camera (outside the frustum or
/// hidden behind the ellipsoid). Conservative: true when unsure (an eye inside the ellipsoid, a
/// sphere too large for a horizon point).
bool sphereMayBeVisible(const Camera& camera, const volume::BoundingSphere& sphere);

/// The columns and rows of `grid` a camera can see: points (every stride-th column and row, stride
/// = max(nx, ny) / 256) whose bottom or top level projects into the frame (4 % margin) and is not
/// hidden by the ellipsoid, widened by one stride on each side. On a grid that wraps in longitude
/// the columns are the shortest arc holding the visible ones (the window may cross the seam); a
/// view that reaches a pole's row, or an arc over 300 degrees, takes every column. A reduced grid's
/// points mark the column of their longitude on its reference axis. Empty: no point visible.
volume::GridWindow visibleGridWindow(const Camera& camera, const volume::GridVolume& grid);
/// The stride visibleGridWindow tests points at (and widens its window by): max(1, max(nx, ny) / 256).
std::size_t visibleGridStride(const volume::GridVolume& grid);

/// The part of the view's columns and rows nearest the eye that fits in `maxPoints` columns x
/// rows, at most `maxColumns` columns and `maxRows` rows (what one texture can hold): the points visibleGridWindow
/// finds visible (the same stride and test) taken in order of their distance from the eye (the nearer of their bottom
/// and top), each widening the window (with a stride of margin on each side, across the seam of a wrapping grid) while
/// it stays within maxPoints; on a wrapping grid at most nx - 1 columns (a window of every column wraps and closes
/// polar caps of its own). What a grid too large for the GPU draws at full resolution where the rest of the view is
/// drawn coarser (GridSourceGL). Empty: no point visible, a reduced grid, a curvilinear grid, or the nearest point's
/// window alone over the caps.
volume::GridWindow nearGridWindow(const Camera& camera, const volume::GridVolume& grid, std::size_t maxPoints,
                                  std::size_t maxColumns = SIZE_MAX, std::size_t maxRows = SIZE_MAX);

/// Where a radar is and how far its volume reaches, from a metadata read (radarFootprint).
struct RadarFootprint {
  volume::BoundingSphere sphere;
  double latDeg = 0.0, lonDeg = 0.0;
  std::string siteName;  ///< "KTLX", "nldhl (Den Helder)": volume::siteTitle of the file's site
};

/// The footprint of the radar volume at `path` (the sphere as radarBoundingSphere says).
Result<RadarFootprint> radarFootprint(const std::string& path, double verticalExaggeration);

/// The bounding sphere of the radar volume at `path` (one file, or the first file of a set or a
/// loop: one site) from a metadata-only read: antenna on the ellipsoid (MSL heights taken as
/// ellipsoidal: the geoid's +-110 m is far inside the margin), radius as the file comment says.
/// A file that gives no gate geometry without its field gets a radius of 500 km (more than any
/// weather radar's range). Errors name the file.
Result<volume::BoundingSphere> radarBoundingSphere(const std::string& path, double verticalExaggeration);

struct CullOutcome {
  std::size_t kept = 0;             ///< radars kept
  std::vector<std::string> culled;  ///< paths of the radars left out
};

/// Removes from `scene.volumes` (and its origins) the radars not visible from `camera` (their sphere as above).
/// A radar whose metadata cannot be read is kept (loading it reports the error).
CullOutcome cullRadarsOutsideView(SceneDescription& scene, const Camera& camera);

/// A radar of a scene left unloaded because the camera did not see it: the layer as described,
/// where it came from (a scene key or a flag, for messages) and its footprint.
struct DeferredRadar {
  VolumeLayerDescription description;
  std::string origin;
  RadarFootprint footprint;
};

/// cullRadarsOutsideView, keeping what was removed: the viewer loads each when
/// sphereMayBeVisible(camera, footprint.sphere) becomes true.
std::vector<DeferredRadar> deferRadarsOutsideView(SceneDescription& scene, const Camera& camera);

}  // namespace atmoglobe::engine
