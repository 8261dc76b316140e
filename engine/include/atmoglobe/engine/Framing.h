#pragma once
// A camera that frames the data a user named, GL-free: `render --grid FILE` or `--radar FILE`
// over the default scene without --camera looks at that data, not at the default scene's place
// (a global grid seen from inside its shell, or a radar elsewhere culled as out of view).
//
// Each volume is an outline and a cap on the sphere: a radar the circle of its bounding radius
// about its site (ViewCulling.h), a grid the edge of its latitude/longitude box from a metadata
// read (describeGridFile; the crop box when the layer has one), each at the ground and 20 km up.
// The caps' union is bounded by one cap about the mean of their centres, where the camera looks
// straight down, north up. Its height is the lowest (bisection, to 0.1 %) at which every outline
// point is in front of the horizon and inside 85 % of the picture's half-width and half-height;
// where no height below the one that shows the whole disc does that (a cap of 90 deg or more, a
// box wider than the visible disc), the whole disc: the limb seen at 85 % of the narrower half
// field of view, h = R / sin(alpha) - R on a sphere of the WGS84 equatorial radius. At least 20 km.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/globe/Result.h>

#include <glm/glm.hpp>

#include <vector>

namespace atmoglobe::engine {

/// A spherical cap: centre and angular radius.
struct GeoCap {
  double latDeg = 0.0, lonDeg = 0.0;
  double radiusDeg = 0.0;
};

/// The cap enclosing a latitude/longitude box (eastDeg may exceed westDeg by up to 360; a span of
/// 360 or more is every longitude: a cap about the pole the box reaches, or the whole sphere).
GeoCap capOfBox(double southDeg, double northDeg, double westDeg, double eastDeg);

/// One cap enclosing all of `caps` (not the smallest: about their mean centre). Empty: an error.
Result<GeoCap> capOfCaps(const std::vector<GeoCap>& caps);

/// What a camera is to frame: where to look from (the cap) and the points to keep in the picture.
struct FramingTarget {
  GeoCap cap;
  std::vector<glm::dvec3> outlineEcef;
};

/// A latitude/longitude box (as capOfBox) and a cap (a circle about its centre) as targets.
FramingTarget framingTargetOfBox(double southDeg, double northDeg, double westDeg, double eastDeg);
FramingTarget framingTargetOfCap(const GeoCap& cap);
/// Several targets as one (their caps by capOfCaps). Empty: an error.
Result<FramingTarget> framingTargetOfTargets(const std::vector<FramingTarget>& targets);

/// The pose described in the header comment.
CameraPose poseFraming(const FramingTarget& target, double fovYDeg, int widthPx, int heightPx);

/// The target of every volume layer of `scene` (metadata reads; errors name the file).
Result<FramingTarget> framingTargetOfVolumes(const SceneDescription& scene);

}  // namespace atmoglobe::engine
