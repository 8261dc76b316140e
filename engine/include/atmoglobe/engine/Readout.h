#pragma once
// The value under the cursor: where the pixel's ray meets the ground (latitude,
// longitude, height above sea level and above the ellipsoid) and, for each volume the ray
// crosses before the ground, the first echo along it: the value with its units and, for radars,
// the site, the gate read (sweep elevation, ray azimuth, gate range) and its stored value: radars
// are sampled nearest-neighbour here, so the readout is a row of `atmoglobe gates`. GL-free:
// the volumes' CPU twins (VolumeGL::referenceSampler, the exact sampling rule in double) are
// sampled along the ray, so the readout is the reference's value, not a guess from the picture.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace atmoglobe::engine {

class SceneRendererGL;

struct CursorReadout {
  std::optional<glm::dvec3> groundLatLonHeight;  ///< lat, lon (deg), 0 m (the ray's ellipsoid hit)
  double seaLevelHeightMeters = 0.0;             ///< of the ground point: minus the EGM96 undulation
  std::vector<std::string> lines;                ///< one per volume hit, then the position
};

/// The readout at pixel (x, y) of `camera` (pixels from the top left, as the mouse gives them).
/// Volumes are searched with `stepMeters` (the first echo is found to within that step along the ray).
CursorReadout readoutAt(const SceneRendererGL& scene, const Camera& camera, double xPx, double yPx,
                        double stepMeters = 100.0);

/// The first sample with a value (VolumeSample::State::Echo) of `sampler` along eye + t dir, t in
/// the sampler's ray interval up to tMaxMeters, searched every `stepMeters` (each volume layer's
/// readout line: VolumeSourceGL::readoutAt).
struct RayValue {
  double tMeters = 0.0;
  double value = 0.0;
  glm::dvec3 ecef{0.0};
};
std::optional<RayValue> firstValueAlong(const volume::VolumeSampler& sampler, const glm::dvec3& eyeEcef,
                                        const glm::dvec3& dir, double tMaxMeters, double stepMeters,
                                        volume::Interpolation interpolation);

/// An ensemble's members and their values at the cursor as one readout line, "  members (10):
/// 0: 251.3 1: 251.6 ...", the first kReadoutMembers of them (then "...").
constexpr std::size_t kReadoutMembers = 16;
std::string memberValuesLine(const std::vector<std::pair<long, double>>& members);

/// Height above mean sea level (EGM96) of a geodetic point; the ellipsoidal height without the grid.
double seaLevelHeightMeters(const globe::Geodetic& point);

}  // namespace atmoglobe::engine
