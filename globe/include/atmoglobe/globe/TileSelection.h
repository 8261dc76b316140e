#pragma once
// Which tiles to draw for a view: quadtree refinement by screen-space error, with frustum
// and horizon culling (GL-free).
//
// The traversal starts at the two level-0 tiles. A tile whose bounding sphere lies wholly
// outside one frustum plane, or whose horizon culling point is hidden behind the
// ellipsoid, is dropped with its subtree. Otherwise it is refined (replaced by its four
// children) while its screen-space error exceeds the budget and it is above the level
// limit, else drawn. The drawn tiles are leaves of one quadtree cut, so they never
// overlap, and every visible part of the surface lies in exactly one of them.
#include <atmoglobe/globe/TileId.h>

#include <glm/glm.hpp>

#include <array>
#include <optional>
#include <vector>

namespace atmoglobe::globe {

/// Quads per tile edge that SelectionOptions and computeTileBounds assume by default.
inline constexpr int kDefaultMeshSegments = 16;

struct ViewState {
  glm::dvec3 eyeEcef{0.0};                        ///< camera position (m, ECEF)
  std::array<glm::dvec4, 6> frustumPlanesEcef{};  ///< (n.xyz, d): n.p + d >= 0 inside; n unit; ECEF metres
  double pixelsPerRadian = 1.0;                   ///< viewportHeightPx / (2 tan(fovY/2))
};

struct TileBounds {
  glm::dvec3 sphereCenterEcef{0.0};  ///< (m, ECEF)
  double sphereRadiusMeters = 0.0;
  std::optional<glm::dvec3> horizonPointEcef;  ///< see horizonCullingPoint (Horizon.h)
};

/// Bounding sphere (and horizon culling point) of tile `t` with surface heights in
/// [minHeightMeters, maxHeightMeters], including the skirts of a mesh built with
/// kDefaultMeshSegments segments and skirtDepthMeters(t, kDefaultMeshSegments).
/// The sphere really encloses it: 33 x 33 samples at the two extreme heights (the distance
/// to the centre is convex along each normal, so its maximum over heights is at an end),
/// plus the longest path from any point of a sample cell to its nearest corner (half a
/// meridian step plus half a parallel step, at radius a^2/b + maxHeight). The margin is
/// about 9 % of the radius (it is first order in the 1/32 sample step).
TileBounds computeTileBounds(const TileId& t, double minHeightMeters = -500.0, double maxHeightMeters = 100.0);
/// The same, for a mesh built with `meshSegments` segments (its skirts hang
/// skirtDepthMeters(t, meshSegments) below the surface).
TileBounds computeTileBounds(const TileId& t, double minHeightMeters, double maxHeightMeters, int meshSegments);

struct SelectionOptions {
  double maxScreenSpaceErrorPx = 2.0;
  int imageryMaxLevel = 2;                  ///< finest level that has imagery: refining past it is only for geometry
  int meshSegments = kDefaultMeshSegments;  ///< quads per tile edge (TileMesh)
  int maxLevel = kMaxTileLevel;
};

struct SelectionStats {
  int visited = 0;        ///< tiles whose bounds were tested
  int culledFrustum = 0;  ///< tiles (with their subtrees) dropped by the frustum
  int culledHorizon = 0;  ///< tiles (with their subtrees) dropped behind the horizon
  int selected = 0;       ///< tiles returned
  int maxLevel = 0;       ///< deepest level returned
};

/// The tiles to draw for this view: leaves of the quadtree that together cover the visible
/// surface exactly once (no overlaps, no gaps among visible ones). Order: depth-first,
/// children north-west, north-east, south-west, south-east. The bounds assume surface
/// heights in [-500, 100] m. The count grows as 1/maxScreenSpaceErrorPx: the caller keeps
/// the budget sane (about a hundred tiles at 2 px, 1000 px high viewport).
std::vector<TileId> selectTiles(const ViewState& view, const SelectionOptions& options,
                                SelectionStats* stats = nullptr);

/// Distance (m) used for the screen-space error: from the eye to the point of the tile at
/// height 0 whose latitude/longitude are the eye's clamped into the tile rectangle (the
/// nearer longitude edge across the antimeridian), or the eye's |height| above the
/// ellipsoid when the eye is over the tile. Never below 1e-3 m. This is the true closest
/// distance when the eye is over the tile; otherwise it can exceed it slightly (the clamped
/// point is not exactly the nearest), which lowers the error a little for far tiles.
double tileDistanceMeters(const TileId& t, const glm::dvec3& eyeEcef);

/// Screen-space error (px) of drawing tile t at this view:
/// geometricErrorMeters * pixelsPerRadian / tileDistanceMeters.
double screenSpaceErrorPx(const TileId& t, const ViewState& view, const SelectionOptions& options);

/// The geometric error (m) of tile t: the larger of
/// (a) chordSagBoundMeters(t, options.meshSegments): how far the flat triangles of the
///     mesh can lie from the ellipsoid, and
/// (b) while t.level < options.imageryMaxLevel, the ground size of one imagery texel: the
///     longest ground extent of the tile (meridian arc at its most poleward latitude or
///     parallel arc at its most equatorward one) divided by 256 px. Past imageryMaxLevel
///     children bring no sharper imagery, so only (a) counts.
double geometricErrorMeters(const TileId& t, const SelectionOptions& options);

/// Upper bound (m) on the distance between the ellipsoid and the mesh of tile t with
/// `segments` quads per edge, in both directions (mesh point to surface, surface point to
/// mesh). Derivation, in scaled space (ellipsoid -> unit sphere): the four corners of a
/// cell lie within angle rho of the cell's centre direction, so every point of their
/// convex hull lies at radius >= cos(rho); scaling back stretches lengths by at most a,
/// so the gap is <= a (1 - cos(rho)), rho maximised over the cells of the tile (the ones
/// nearest the equator). a when rho >= 90 degrees. Measured (TileMeshTest): the vertices of
/// the four children come within 98-100 % of this bound, 16 segments, levels 0 to 18.
double chordSagBoundMeters(const TileId& t, int segments);

}  // namespace atmoglobe::globe
