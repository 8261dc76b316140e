// The radar beam geometry shared by the radar kinds (sample_polar.glsl: one radar; sample_network.glsl:
// many). Included once per program, before the volumes, by a sampler file's "// @NEEDS polar_beam.glsl"
// line (VolumeRendererGL::marchProgram). Float32 twins of volume::LocalSphereBeam (Geolocation.h).

// volume::LocalSphereBeam::unexaggerateEnu: a point drawn at vertical exaggeration e moved back to
// its true height h / e along the local sphere's normal. l: ENU at the antenna (m); h0 the antenna's
// height above the ellipsoid, M and N the site's meridional and prime-vertical radii (m).
vec3 polarUnexaggerateEnu(vec3 l, float h0, float M, float N, float e) {
  float dh0 = length(l.xy);
  float c0 = dh0 > 0.0 ? l.y / dh0 : 1.0, s0 = dh0 > 0.0 ? l.x / dh0 : 0.0;
  float rc0 = 1.0 / (c0 * c0 / M + s0 * s0 / N) + h0;
  float w0 = l.z + rc0;
  float dl0 = sqrt(dh0 * dh0 + w0 * w0);
  float hh = h0 + (dh0 * dh0 + l.z * l.z + 2.0 * l.z * rc0) / (dl0 + rc0);
  return l - (1.0 - 1.0 / e) * hh / dl0 * vec3(l.xy, w0);
}

// volume::LocalSphereBeam::antennaCoordinates: ENU (m) -> (range m, azimuth deg, elevation deg).
// straight: straight-line beams (range and elevation of the chord); else the effective-Earth
// (radius re) beam over the local sphere with the ellipsoid's normal-section radius in this azimuth.
vec3 polarAntennaCoordinatesEnu(vec3 l, float h0, float M, float N, float re, bool straight) {
  float dh = length(l.xy);
  float az = degrees(atan(l.x, l.y));
  if (az < 0.0) az += 360.0;
  if (straight) {
    float r = length(l);
    return vec3(r, az, degrees(asin(clamp(l.z / max(r, 1e-6), -1.0, 1.0))));
  }
  // Local sphere with the ellipsoid's normal-section radius in this azimuth (Euler).
  // 1 / (cos^2 / M + sin^2 / N) of the azimuth, with one division.
  float rAlpha = dh > 0.0 ? dh * dh / (l.y * l.y / M + l.x * l.x / N) : M;
  float rc = rAlpha + h0;
  float w = l.z + rc;
  float dl = sqrt(dh * dh + w * w);
  float h = h0 + (dh * dh + l.z * l.z + 2.0 * l.z * rc) / (dl + rc);  // |d| - rc without cancellation
  // The arc s = rAlpha atan(dh / w) and sin(gamma / 2) by their Taylor series: the angles are
  // small (dh / w <= 0.4 up to 2,500 km from the antenna, where the series' first omitted term is
  // 1e-8 of the arc; gamma / 2 <= 0.15 there, 1e-13), and the series are a fraction of the
  // instructions of atan and sin, which llvmpipe runs at every sample. cos(gamma / 2) from
  // sin(gamma / 2): sin(gamma) = 2 sin(gamma / 2) cos(gamma / 2).
  float x = dh / w, x2 = x * x;
  float s = rAlpha * x *
            (1.0 + x2 * (-1.0 / 3.0 + x2 * (1.0 / 5.0 + x2 * (-1.0 / 7.0 + x2 * (1.0 / 9.0 + x2 * (-1.0 / 11.0 + x2 * (1.0 / 13.0 - x2 / 15.0)))))));
  // Effective-Earth beam inverse (Doviak & Zrnic 1993, eq. 2.28) in the cancellation-free form.
  float gamma = s / re;
  float rho1 = re + h0, rho2 = re + h;
  float hg = 0.5 * gamma, hg2 = hg * hg;
  float sg = hg * (1.0 + hg2 * (-1.0 / 6.0 + hg2 * (1.0 / 120.0 - hg2 / 5040.0)));
  float dz = h - h0;
  float r = sqrt(dz * dz + 4.0 * rho1 * rho2 * sg * sg);
  float el = degrees(atan(dz - 2.0 * rho2 * sg * sg, 2.0 * rho2 * sg * sqrt(1.0 - sg * sg)));
  return vec3(r, az, el);
}
