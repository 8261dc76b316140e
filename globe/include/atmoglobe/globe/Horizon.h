#pragma once
// Ellipsoidal horizon culling in "scaled space" (GL-free).
//
// Scaled space divides ECEF coordinates by the WGS84 radii (a, a, b), which turns the
// ellipsoid into the unit sphere. The map is linear, so "the segment from the eye to P
// passes through the ellipsoid" is the same statement before and after scaling, and the
// sphere makes the test cheap. The idea (a horizon plane plus the silhouette cone, and one
// conservative "culling point" per tile) is the one described in the public CesiumJS
// documentation and blog posts on horizon culling; the derivation here is our own:
//
// * Eye V (|V| > 1) and point P, both in scaled space. The visible cap of the sphere is
//   {X : X.V >= 1}. A point outside the sphere is hidden iff it lies inside the cone of
//   tangent rays from V (((P-V).V)^2 > |P-V|^2 (|V|^2-1) with (P-V).V < 0) and beyond the
//   horizon plane (P.V < 1). This is exact for points outside the ellipsoid; points
//   inside it on the eye's side of the horizon plane are reported visible (conservative).
// * V and P (both outside the sphere) see each other iff some tangent plane has both on
//   its outer side (separating-plane theorem), i.e. iff the cap sets C(V) and C(P)
//   intersect, where C(X) = {unit n : n.X >= 1} (angular radius acos(1/|X|) about X).
//   So if C(P) is inside C(Q) for every point P of a tile, "Q hidden" implies "every P
//   hidden". C(P) is inside C(Q) for Q = m d (unit d) iff angle(P, d) + acos(1/|P|) <=
//   acos(1/m). C(.) of a convex combination lies in the union of the C(.)s, so a finite
//   set of samples whose convex hull lies radially outside the tile surface is enough.
#include <atmoglobe/globe/TileId.h>

#include <glm/glm.hpp>

#include <optional>

namespace atmoglobe::globe {

/// Geodetic -> ECEF (m) from the sine and cosine of latitude and longitude and the height
/// (m): the textbook prime-vertical-radius formula GeographicLib's Forward also uses. For
/// loops over grids where the sines are computed once per row/column; it differs from
/// geodeticToEcef only by the rounding of the caller's sines (at 90 deg, cos(pi/2) in
/// radians is 6e-17, not 0: a 4e-10 m offset).
glm::dvec3 ecefFromSinCos(double sinLat, double cosLat, double sinLon, double cosLon, double heightMeters);

/// ECEF (m) -> scaled space (ECEF divided by (a, a, b); dimensionless).
glm::dvec3 ecefToScaledSpace(const glm::dvec3& ecef);
/// Scaled space -> ECEF (m).
glm::dvec3 scaledSpaceToEcef(const glm::dvec3& scaled);

/// The scaled-space occlusion test (both arguments in scaled space). false when the eye is
/// inside or on the unit sphere (nothing is culled then).
bool isScaledSpacePointOccluded(const glm::dvec3& eyeScaled, const glm::dvec3& pointScaled);

/// true if `pointEcef` is hidden behind the WGS84 ellipsoid seen from `eyeEcef` (metres,
/// ECEF). Exact (up to rounding) for points outside the ellipsoid; a point below the
/// surface on the near side of the horizon plane is reported visible. false whenever the
/// eye is not outside the ellipsoid.
bool isOccludedByEllipsoid(const glm::dvec3& eyeEcef, const glm::dvec3& pointEcef);

/// A point (ECEF, m) that is hidden behind the ellipsoid, as seen from any eye, only if
/// every point of tile `t` with heights in [minHeightMeters, maxHeightMeters] is hidden.
/// std::nullopt when no such point exists (tiles whose points, with their horizons, span
/// 90 degrees or more about the tile centre: levels 0 and sometimes 1).
///
/// Method: 9 x 9 samples over the tile (latitudes padded by half a sample step so the
/// small-circle edges are covered), placed in scaled space at a common radius
/// F = (1 + max(maxHeight, 0)/b) / cos(rho), rho being the largest angle between a sample
/// cell's centre direction and its corners; that puts the convex hull of the samples
/// radially outside the whole tile surface up to maxHeight. Then m = 1 / cos(max angle to
/// the tile's centre direction + acos(1/F)). Points below the ellipsoid are always hidden,
/// so minHeightMeters only matters through maxHeight < 0 (treated as 0). Conservative, and
/// measured for heights 0: the point is ~1.46x as high above the tile as a point whose
/// horizon just reaches the tile's corners (19 m vs 13 m at level 10, 1.2 m vs 0.8 m at
/// level 12). Cost ~4 us.
std::optional<glm::dvec3> horizonCullingPoint(const TileId& t, double minHeightMeters, double maxHeightMeters);

}  // namespace atmoglobe::globe
