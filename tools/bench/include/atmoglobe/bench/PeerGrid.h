#pragma once
// The peer's input: a volume resampled onto a Cartesian grid in a local ENU frame. Radar volumes
// through a fast inverse (ENU -> antenna coordinates) whose error against the exact one is
// measured; any other kind (forecast grids) through its own exact VolumeSampler, with the
// trilinear reconstruction's error measured and bounded.
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/VolumeSampler.h>

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
  /// Sampler-resampled grids: the frame (ECEF origin of the ENU axes the grid is laid in), and
  /// the trilinear reconstruction's error against the sampler (field units, values below the
  /// transfer function's zero-opacity value taken as that value) at random points of the box.
  glm::dvec3 frameOriginEcef{0.0};
  glm::dmat3 frameEnuToEcef{1.0};
  double maxReconstructionError = 0.0, rmsReconstructionError = 0.0;
  int reconstructionPoints = 0;
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

/// ENU axes (columns east, north, up in ECEF) at a geodetic point, and the point.
struct PeerFrame {
  glm::dvec3 originEcef{0.0};
  glm::dmat3 enuToEcef{1.0};
  glm::dvec3 toEcef(const glm::dvec3& enu) const { return originEcef + enuToEcef * enu; }
  glm::dvec3 toEnu(const glm::dvec3& ecef) const { return glm::transpose(enuToEcef) * (ecef - originEcef); }
};
PeerFrame enuFrameAt(double latDeg, double lonDeg, double heightMeters);

/// The layout over the box [lo, hi] (frame metres, margins included): `nativeSpacingMeters`
/// unless a side would exceed 2048 voxels or the grid `maxVoxels`, then coarsened uniformly (the
/// reason says from what). Voxel (0,0,0)'s centre at lo.
PeerGrid layoutPeerGrid(const glm::dvec3& lo, const glm::dvec3& hi, double nativeSpacingMeters, double maxVoxels);

/// The box of a forecast grid's visible data in `frame`: every grid point whose value is above
/// `visibleAbove`, plus a margin of one horizontal grid spacing (the cells around them); the
/// native spacing is the finest level spacing at those points (a Cartesian grid must resolve the
/// levels). False when no value is visible.
bool gridPeerBox(const volume::GridVolume& grid, const PeerFrame& frame, double visibleAbove, glm::dvec3* lo,
                 glm::dvec3* hi, double* nativeSpacingMeters);

/// Fills `values` (x fastest) with the sampler's linear sample at each voxel centre of `g`
/// (frame -> ECEF in double: the sampler's exact rule, no approximation); no echo / no data ->
/// `emptyValue`. Sets g.resampleSeconds and the frame.
void resampleSampler(const volume::VolumeSampler& sampler, const PeerFrame& frame, PeerGrid& g, double emptyValue,
                     int threads, std::vector<float>* values);

/// Trilinear interpolation of `values` at frame point `enu` (what VTK's linear interpolation
/// does between voxel centres); `emptyValue` outside the grid.
double trilinearAt(const PeerGrid& g, const std::vector<float>& values, const glm::dvec3& enu, double emptyValue);

/// The resampled grid against the sampler at `samples` uniformly random points of the grid's box
/// (seeded): max and RMS of |max(trilinear, floor) - max(sample, floor)|, non-echo samples taken
/// as emptyValue. Stored into g.
void measureReconstructionError(const volume::VolumeSampler& sampler, const PeerFrame& frame, PeerGrid& g,
                                const std::vector<float>& values, double emptyValue, double floorValue, int samples,
                                std::uint64_t seed = 12345);

/// The classical bound on trilinear interpolation between samples h apart of a field with
/// bounded second derivatives: |f - I f| <= h^2 / 8 (max|f_xx| + max|f_yy| + max|f_zz|).
double trilinearErrorBound(double spacingMeters, double sumMaxSecondDerivatives);

}  // namespace atmoglobe::bench
