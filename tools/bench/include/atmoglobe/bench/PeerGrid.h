#pragma once
// The peer's input: a radar volume resampled onto a Cartesian grid in the site's ENU frame, with
// a fast inverse (ENU -> antenna coordinates) whose error against the exact one is measured.
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace atmoglobe::bench {

/// Fast inverse for resampling (ENU relative to the antenna -> antenna coordinates): the Earth
/// near the site replaced by a sphere of radius rs (the Gaussian radius of curvature sqrt(M N) at
/// the site) touching the ellipsoid below the antenna; height above it and arc distance on it,
/// then the effective-Earth beam model (Doviak & Zrnic 1993, eq. 2.28) inverted in closed form.
///
/// Error against volume::antennaCoordinatesExact: the ellipsoid departs from the sphere along an
/// azimuth by d(s) = s^2 eps / (2 rs) + e^2 |sin lat cos lat| s^3 / (2 M^2) + e^2 s^4 / (8 M^3) at
/// ground distance s, eps = sqrt(N/M) - 1 ~ e'^2 cos^2(lat) / 2 (the sphere's radius against the
/// normal-section radius, then the curvature changing with latitude along the path); heights are
/// off by up to d(s), arc distances by eps s^3 / (6 rs^2) + h d'(s). At 460 km: up to 56 m of
/// height, 0.007 deg of elevation (KLBB's echo box: 1.6 m of range, 0.004 deg of elevation).
/// The derivation and the test holding the inverse and the resampled values to it:
/// tests/bench/BenchPeerGridTest.cpp; buildPeerGrid measures it per grid for the report.
struct FastInverse {
  double rs = 0.0;  ///< local sphere radius (m)
  double h0 = 0.0;  ///< antenna height above the ellipsoid (m)
  double re = 0.0;  ///< effective Earth radius of the beam model (m)

  /// Antenna coordinates of a point in the site's ENU frame (m, origin at the antenna).
  volume::AntennaCoordinates operator()(const glm::dvec3& enu) const;
  /// The forward model on the same sphere: ENU (m) of (range m, azimuth deg, elevation deg).
  glm::dvec3 forward(double rangeMeters, double azDeg, double elDeg) const;
};

FastInverse fastInverseFor(const volume::PolarVolume& v);

/// Largest differences of the fast inverse from the exact one over a set of points.
struct InverseError {
  double maxRangeMeters = 0.0, maxAzimuthDeg = 0.0, maxElevationDeg = 0.0;
  int points = 0;  ///< points compared (inside [1 km, maxRange])
};

/// The fast inverse against volume::antennaCoordinatesExact at `samples` uniformly random points
/// of the ENU box [lo, hi] (seeded: reproducible), skipping those outside [1 km, v.maxRangeMeters].
InverseError measureFastInverseError(const volume::PolarVolume& v, const FastInverse& inverse, const glm::dvec3& lo,
                                     const glm::dvec3& hi, int samples, std::uint64_t seed = 12345);

struct PeerGrid {
  int nx = 0, ny = 0, nz = 0;
  double spacingMeters = 0.0;
  glm::dvec3 originEnu{0.0};  ///< centre of voxel (0,0,0), ENU at the antenna (m)
  double nativeSpacingMeters = 0.0;
  std::string coarsenedReason;
  double maxRangeErrorMeters = 0.0, maxAzimuthErrorDeg = 0.0, maxElevationErrorDeg = 0.0;
  double resampleSeconds = 0.0;
  double bytes() const { return static_cast<double>(nx) * ny * nz * sizeof(float); }
};

/// Resamples `v` onto a Cartesian ENU grid at the finest gate spacing over the bounding box of
/// the gates that can be seen (value above `visibleAbove`, the transfer function's zero-opacity
/// value) plus two gate spacings, coarsened uniformly when a side would exceed 2048 voxels
/// (GL_MAX_3D_TEXTURE_SIZE) or the grid `maxVoxels`. Voxels get the linear sampling rule's value
/// (samplePolar) at the fast inverse's antenna coordinates; no echo / no data become `emptyValue`
/// (zero opacity). The fast inverse's error over 20000 random voxels is measured into the grid.
/// `values`: x fastest, then y, then z. No visible gate: nx == 0 and `values` untouched.
PeerGrid buildPeerGrid(const volume::PolarVolume& v, double emptyValue, double visibleAbove, double maxVoxels,
                       int threads, std::vector<float>* values);

}  // namespace atmoglobe::bench
