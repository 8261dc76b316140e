#pragma once
// Triangle mesh of one tile on the WGS84 ellipsoid, ready to upload (GL-free).
//
// Positions are float32 offsets from a double-precision centre (float32 ECEF itself has
// only ~0.5 m resolution); every double -> float narrowing is an explicit static_cast.
#include <atmoglobe/globe/TileId.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace atmoglobe::globe {

struct TileMesh {
  glm::dvec3 centerEcef{0.0};                        ///< double-precision origin of the float positions (m, ECEF)
  std::vector<glm::vec3> positionsRelativeToCenter;  ///< float32 ECEF offsets from centerEcef (m)
  std::vector<glm::vec2> texCoords;                  ///< (u east, v south) in [0,1] within the tile
  std::vector<glm::vec3> normals;                    ///< outward ellipsoid normal (unit, ECEF)
  std::vector<std::uint32_t> indices;                ///< triangles, counter-clockwise seen from outside (above)
};

/// Number of vertices of the grid part of a mesh (they come first; the skirt follows).
inline std::size_t tileMeshGridVertexCount(int segments) {
  return static_cast<std::size_t>(segments + 1) * static_cast<std::size_t>(segments + 1);
}

/// Builds the mesh of tile t.
///
/// Layout: first the (segments+1)^2 grid vertices on the ellipsoid (height 0), row-major,
/// row j = 0 at the tile's north edge (v = j/segments), column i = 0 at its west edge
/// (u = i/segments): index j*(segments+1)+i. Then the skirt: 4*segments vertices, one
/// below each edge vertex (same texcoord and normal, skirtDepthMeters below it along the
/// normal), going round the tile counter-clockwise seen from above starting at the
/// north-west corner: down the west edge, east along the south edge, up the east edge,
/// west along the north edge. Skirt triangles face away from the tile (a viewer looking
/// into a crack from outside sees their front).
///
/// Grid triangles: each cell (NW a, NE b, SW c, SE d) gives (c, d, b) and (c, b, a). At
/// a pole the edge row is exactly the pole point (0, 0, +-b): one triangle of each polar
/// cell is degenerate (zero area, finite values).
/// The centre is the middle of the grid vertices' bounding box. Precision: float32 offsets
/// carry a rounding error of at most half an ulp of the largest offset per component
/// (~0.5 mm for tiles under ~30 km, level >= 10; ~0.25 m for a level-0 tile).
/// Preconditions (asserted): isValid(t), segments >= 1, skirtDepthMeters >= 0.
TileMesh buildTileMesh(const TileId& t, int segments, double skirtDepthMeters);

/// Skirt depth (m) that hides the cracks along the edges of tile t (mesh with `segments`
/// quads per edge). A crack opens where a coarser neighbour's edge chord sags below this
/// tile's edge vertices; it is at most that neighbour's chord sag. Chosen as the chord-sag
/// bound (chordSagBoundMeters) of an equatorial tile (the worst latitude) two levels
/// coarser than t (covers neighbours up to two levels coarser: the sag grows 4x per level),
/// level 0 itself for levels 0 and 1, and at least 4 float32 ulps of the tile's width
/// (rounding of the vertex offsets).
double skirtDepthMeters(const TileId& t, int segments);

}  // namespace atmoglobe::globe
