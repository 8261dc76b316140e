#include <atmoglobe/volume/ConeMesh.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace atmoglobe::volume {

glm::dvec3 conePointEnu(const GeolocationSite& site, const ConeMeshOptions& options, double azimuthDeg,
                        double elevationDeg, double rangeMeters) {
  if (options.straight) {
    const double horizontal = rangeMeters * std::cos(degreesToRadians(elevationDeg));
    return {horizontal * std::sin(degreesToRadians(azimuthDeg)), horizontal * std::cos(degreesToRadians(azimuthDeg)),
            rangeMeters * std::sin(degreesToRadians(elevationDeg))};
  }
  const GatePosition p = geolocateGateExact(site, options.beam, azimuthDeg, elevationDeg, rangeMeters);
  const glm::dvec3 antennaEcef =
      globe::geodeticToEcef(globe::Geodetic{site.latDeg, site.lonDeg, site.antennaHeightEllipsoidMeters});
  const glm::dmat3 axes = globe::enuAxes(site.latDeg, site.lonDeg);  // columns E, N, U
  return glm::transpose(axes) * (p.ecef - antennaEcef);
}

ConeMesh buildConeMesh(const GeolocationSite& site, const Sweep& sweep, const SweepImage& image,
                       const ConeMeshOptions& options) {
  assert(image.width > 0 && image.height > 0 && image.gateSpacingMeters > 0);
  assert(std::isfinite(sweep.fixedAngleDeg) && std::abs(sweep.fixedAngleDeg) < 90.0);
  ConeMesh mesh;
  mesh.elevationDeg = sweep.fixedAngleDeg;

  // Azimuth columns: every k-th row boundary, closing the turn, plus azimuth 0 (mod 360).
  const std::size_t rows = static_cast<std::size_t>(image.height);
  const std::size_t maxColumns =
      static_cast<std::size_t>(std::max(2, std::min(options.maxAzimuthColumns, options.maxTriangles / 4 - 1)));
  const std::size_t step = (rows + maxColumns - 1) / maxColumns;
  const double turnStart = image.rowStartAzimuthDeg.front();
  std::vector<double> cols;
  for (std::size_t r = 0; r < rows; r += step) cols.push_back(image.rowStartAzimuthDeg[r]);
  const double zero = turnStart <= 0.0 ? 0.0 : 360.0;  // azimuth 0 inside [turnStart, turnStart + 360)
  cols.push_back(zero);
  cols.push_back(turnStart + 360.0);
  std::sort(cols.begin(), cols.end());
  cols.erase(std::unique(cols.begin(), cols.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
             cols.end());
  if (cols.size() < 3) {  // a single row and azimuth 0 on its boundary: split the turn in thirds
    cols = {turnStart, turnStart + 120.0, turnStart + 240.0, turnStart + 360.0};
  }
  mesh.columnAzimuthDeg = cols;
  const std::size_t segmentsAz = cols.size() - 1;

  // Range rows: first gate centre to last used gate centre.
  const double r0 = std::max(sweep.firstGateRangeMeters, 1.0);  // no apex: no degenerate triangles
  const double r1 = std::max(sweep.gateRangeMeters(static_cast<std::uint32_t>(image.width - 1)), r0 + 1.0);
  const int budgetRows = options.maxTriangles / static_cast<int>(2 * segmentsAz);
  assert(budgetRows >= 1);
  const int segmentsRange = std::clamp(budgetRows, 1, options.maxRangeRows);
  for (int k = 0; k <= segmentsRange; ++k) {
    mesh.rowRangeMeters.push_back(k == segmentsRange ? r1 : r0 + (r1 - r0) * k / segmentsRange);
  }

  const std::size_t nr = mesh.rowRangeMeters.size();
  mesh.positionsEnu.reserve(cols.size() * nr);
  mesh.texCoords.reserve(cols.size() * nr);
  for (std::size_t c = 0; c < cols.size(); ++c) {
    // v by azimuth (row intervals), not by index; the closing column gets v = 1 exactly.
    const double v = c + 1 == cols.size() ? 1.0 : sweepImageV(image, cols[c]);
    for (std::size_t k = 0; k < nr; ++k) {
      const glm::dvec3 p = conePointEnu(site, options, cols[c], sweep.fixedAngleDeg, mesh.rowRangeMeters[k]);
      mesh.positionsEnu.push_back(glm::vec3(p));  // double -> float32 narrowing (<= 0.016 m below 524 km)
      mesh.texCoords.push_back(
          glm::vec2(static_cast<float>(sweepImageU(image, mesh.rowRangeMeters[k])), static_cast<float>(v)));
    }
  }
  // Bounds of the float positions, so that glTF accessor min/max match the data exactly.
  mesh.minEnu = mesh.positionsEnu.front();
  mesh.maxEnu = mesh.positionsEnu.front();
  for (const glm::vec3& p : mesh.positionsEnu) {
    mesh.minEnu = glm::min(mesh.minEnu, p);
    mesh.maxEnu = glm::max(mesh.maxEnu, p);
  }

  for (std::size_t c = 0; c < segmentsAz; ++c) {
    for (std::size_t k = 0; k + 1 < nr; ++k) {
      const std::uint32_t a = mesh.vertexIndex(c, k), b = mesh.vertexIndex(c + 1, k);
      const std::uint32_t d = mesh.vertexIndex(c + 1, k + 1), e = mesh.vertexIndex(c, k + 1);
      // Counter-clockwise seen from above (+U): the upper side is the front face.
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, e});
    }
  }
  assert(static_cast<int>(mesh.triangleCount()) <= options.maxTriangles);
  return mesh;
}

}  // namespace atmoglobe::volume
