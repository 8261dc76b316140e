#pragma once
// The legacy "radar cone": each PPI sweep as a textured surface of revolution around the antenna.
//
// The surface runs from the first gate's centre to the last gate's centre (slant range) at the
// sweep's fixed elevation, all the way round. Bent (default): each vertex is where the beam
// centre is under the effective-Earth-radius model (geolocateGateExact: Doviak & Zrnic 2.28
// height and ground distance, WGS84 geodesic from the site), expressed in the local east-north-up
// frame at the antenna. Straight (--straight): (r cos el sin az, r cos el cos az, r sin el) in
// that ENU frame, the cone older viewers draw (no refraction, no Earth curvature).
//
// Tessellation: azimuth columns at ray boundaries of the sweep image (every k-th so that at most
// 720 columns are used) plus azimuth 0 (the seam is duplicated with v = 0 and v = 1); range rows
// evenly spaced in slant range, as many as fit in the triangle budget (at most 64). Vertices lie
// exactly on the beam surface; triangles cut chords: the sag is r (1 - cos(dAz / 2)) across
// azimuth (4.4 m at 460 km with 720 columns, 17.5 m with 360) and under 5 m along range for 16+
// rows to 460 km (beam curvature radius > 4 R) -- small against a beam 3.8 km wide at 230 km.
//
// Precision: positions are float32 ENU metres relative to the antenna (double until the narrowing
// in buildConeMesh). Rounding error <= half an ulp per coordinate: 2^-6 m = 0.016 m below 524 km.
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/SweepImage.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace atmoglobe::volume {

/// Google Earth draws at most this many triangles per model (Google's KML Reference, <Model>).
inline constexpr int kGoogleEarthMaxTrianglesPerModel = 21845;

struct ConeMeshOptions {
  bool straight = false;  ///< straight cone instead of the bent beam surface
  BeamModel beam;         ///< used when not straight (default ke 4/3, WGS84 radius at the site)
  int maxTriangles = kGoogleEarthMaxTrianglesPerModel;  ///< budget per cone (>= 4 * columns)
  int maxAzimuthColumns = 720;
  int maxRangeRows = 64;
};

struct ConeMesh {
  double elevationDeg = 0.0;             ///< the sweep's fixed angle (degrees)
  std::vector<glm::vec3> positionsEnu;   ///< m, local ENU at the antenna (float32)
  std::vector<glm::vec2> texCoords;      ///< (u, v): u along range, v along azimuth, v = 0 at row 0 (glTF)
  std::vector<std::uint32_t> indices;    ///< triangle list
  std::vector<double> columnAzimuthDeg;  ///< azimuth of each vertex column (increasing, one full turn)
  std::vector<double> rowRangeMeters;    ///< slant range of each vertex row (m)
  glm::vec3 minEnu{0.0f}, maxEnu{0.0f};  ///< bounds of positionsEnu
  /// Vertex index of (column, row); vertices are column-major.
  std::uint32_t vertexIndex(std::size_t column, std::size_t row) const {
    return static_cast<std::uint32_t>(column * rowRangeMeters.size() + row);
  }
  std::size_t triangleCount() const { return indices.size() / 3; }
};

/// Builds the cone of `sweep` textured by `image` (built from the same sweep) from the first gate
/// centre to the centre of gate image.width - 1. `site` from resolveSite (antenna height above
/// the ellipsoid). Preconditions (asserted): image non-empty, gate spacing > 0, finite elevation
/// in (-90, 90), options.maxTriangles >= 4 * 2 columns.
ConeMesh buildConeMesh(const GeolocationSite& site, const Sweep& sweep, const SweepImage& image,
                       const ConeMeshOptions& options);

/// ENU (m, at the antenna) of a cone point at slant range `rangeMeters`, azimuth and elevation in
/// degrees, in double: what buildConeMesh computes before narrowing to float.
glm::dvec3 conePointEnu(const GeolocationSite& site, const ConeMeshOptions& options, double azimuthDeg,
                        double elevationDeg, double rangeMeters);

}  // namespace atmoglobe::volume
