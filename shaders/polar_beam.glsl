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
  float ca = dh > 0.0 ? l.y / dh : 1.0, sa = dh > 0.0 ? l.x / dh : 0.0;
  float rAlpha = 1.0 / (ca * ca / M + sa * sa / N);
  float rc = rAlpha + h0;
  float w = l.z + rc;
  float dl = sqrt(dh * dh + w * w);
  float h = h0 + (dh * dh + l.z * l.z + 2.0 * l.z * rc) / (dl + rc);  // |d| - rc without cancellation
  float s = rAlpha * atan(dh, w);
  // Effective-Earth beam inverse (Doviak & Zrnic 1993, eq. 2.28) in the cancellation-free form.
  float gamma = s / re;
  float rho1 = re + h0, rho2 = re + h;
  float sg = sin(0.5 * gamma);
  float dz = h - h0;
  float r = sqrt(dz * dz + 4.0 * rho1 * rho2 * sg * sg);
  float el = degrees(atan(dz - 2.0 * rho2 * sg * sg, rho2 * sin(gamma)));
  return vec3(r, az, el);
}
