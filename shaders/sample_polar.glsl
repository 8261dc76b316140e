// Sampler of a radar volume in its own polar geometry (spec: volume/PolarVolume.h), included
// once per radar of a march with VOL_ replaced by that volume's prefix (engine/VolumeGL.h).
//
// Positions are float32 relative to the antenna (the site's ECEF subtracted in double on the
// CPU). Each sample: site-relative ECEF -> (range, azimuth, elevation) by the beam model, then
// the sampling rule of PolarVolume.h (sweeps bracketing the elevation, rays by azimuth, gates by
// range; nearest or linear). The ray interval: the clip sphere and the band of straight
// elevations that holds every beam (volume::straightElevationBand at the clip radius).
//
// Variant constants (defines, one program per combination):
//   VOL_INTERPOLATION  0 nearest, 1 linear
//   VOL_BEAM           0 effective-Earth (4/3) on the local sphere, 1 straight lines
//   VOL_EXAGGERATED    1: a vertical exaggeration is drawn (volume/VerticalExaggeration.h): each
//                      point is moved back to its true height on the local sphere first
// Injected constants: MAX_SWEEPS, RAY_TABLE_BINS, ELEVATION_BINS, STATE_ECHO, STATE_NOT_ECHO.
// @NEEDS polar_beam.glsl

uniform sampler2DArray VOL_values;    // RG16F, linear (nearest sampler for nearest interpolation): [sweep] (rays + 1) x (gates + 1): (value if echo else 0, 1 if echo else 0)
uniform vec2 VOL_valuesInvSize;       // 1 / (gates + 1, rays + 1) of a layer
uniform sampler1DArray VOL_rayTable;  // R32F, linear: [sweep] ray coordinate at azimuth j * 360 / RAY_TABLE_BINS;
                                      // layer sweepCount: texel b < ELEVATION_BINS = last sweep with elevation <= bin b's start, -1 none
uniform vec2 VOL_elLookupRange;       // elevations (deg) of the lookup's first bin start and last bin end
uniform vec4 VOL_sweepGeom[MAX_SWEEPS];  // elevationDeg, firstGateRange, gateSpacing, gateCount
uniform int VOL_sweepRays[MAX_SWEEPS];
uniform int VOL_sweepCount;
uniform float VOL_halfBeamDeg;
uniform float VOL_maxRange;                 // clip sphere radius (m)
uniform vec2 VOL_straightElevationClipSin;  // sin of the straight-line elevation band that holds every beam
uniform mat3 VOL_ecefToEnu;                 // rows: east, north, up at the site
uniform float VOL_h0;                       // antenna height above the ellipsoid (m)
uniform float VOL_meridionalRadius;         // M at the site (m)
uniform float VOL_primeVerticalRadius;      // N at the site (m)
uniform float VOL_effectiveRadius;          // Re = ke * R (m)
uniform float VOL_exaggeration;             // vertical exaggeration (1: none)
uniform vec2 VOL_cellScale;                 // the step rule's (volume::PolarCellScale): gate (m; 0: no rule),
                                            // angle across the beam (rad)

// --- geometry: site-relative ECEF -> (range m, azimuth deg, elevation deg) ---------------
// The float32 twin of volume::LocalSphereBeam::antennaCoordinates (polar_beam.glsl).
vec3 VOL_antennaCoordinates(vec3 p) {
  vec3 l = VOL_ecefToEnu * p;  // east, north, up
#if VOL_EXAGGERATED
  l = polarUnexaggerateEnu(l, VOL_h0, VOL_meridionalRadius, VOL_primeVerticalRadius, VOL_exaggeration);
#endif
  return polarAntennaCoordinatesEnu(l, VOL_h0, VOL_meridionalRadius, VOL_primeVerticalRadius, VOL_effectiveRadius,
                                    VOL_BEAM == 1);
}

vec3 VOL_debugCoordinates(vec3 p) { return VOL_antennaCoordinates(p); }

// --- the sampling rule (PolarVolume.h) ---------------------------------------------------
// Ray coordinate in [-1, n): the sweep's table interpolated linearly (volume::rayCoordinateTable;
// below 0 it lies between the last ray and ray 0).
float VOL_rayCoordinate(int k, float az) {
  float u = (az * (float(RAY_TABLE_BINS) / 360.0) + 0.5) / float(RAY_TABLE_BINS + 1);
  return textureLod(VOL_rayTable, vec2(u, float(k)), 0.0).r;
}

// Adds sweep k's contribution with weight w: echo weight and weighted sum of echo values.
void VOL_sampleSweep(int k, float w, vec3 rae, inout float echoW, inout float sumV) {
  vec4 g = VOL_sweepGeom[k];
  float gc = (rae.x - g.y) / g.z;
  if (gc < -0.5 || gc > g.w - 0.5) return;  // outside this sweep's gates: no data
  int n = VOL_sweepRays[k];
  // One fetch: bilinear over (gate, ray) with the linear filter, or the nearest texel (round)
  // when the host binds a nearest sampler; row n repeats ray 0, column gateCount the last gate.
  float a = VOL_rayCoordinate(k, rae.y);
  float y = a < 0.0 ? a + float(n) : a;
  vec2 texel = textureLod(VOL_values, vec3((gc + 0.5) * VOL_valuesInvSize.x, (y + 0.5) * VOL_valuesInvSize.y, float(k)), 0.0).rg;
  sumV += w * texel.x;
  echoW += w * texel.y;
}

// The last sweep at or below the elevation: the lookup gives the last sweep at or below the
// bin's start; at most a few sweeps can start inside one bin, so the scan after it is short.
int VOL_sweepAtOrBelow(float el) {
  int n = VOL_sweepCount;
  int bin = clamp(int((el - VOL_elLookupRange.x) / (VOL_elLookupRange.y - VOL_elLookupRange.x) * float(ELEVATION_BINS)), 0,
                  ELEVATION_BINS - 1);
  int k = int(texelFetch(VOL_rayTable, ivec2(bin, VOL_sweepCount), 0).r);
  for (int it = 0; it < MAX_SWEEPS && k + 1 < n && VOL_sweepGeom[k + 1].x <= el; ++it) ++k;
  return k;
}

// Brackets the elevation: sweeps (k0, k1) with weights (1 - t, t); k0 < 0: outside.
ivec2 VOL_bracket(float el, out float t) {
  t = 0.0;
  int n = VOL_sweepCount;
  float e0 = VOL_sweepGeom[0].x, en = VOL_sweepGeom[n - 1].x;
  if (el < e0 - VOL_halfBeamDeg || el > en + VOL_halfBeamDeg) return ivec2(-1);
  if (el <= e0) return ivec2(0, 0);
  if (el >= en) return ivec2(n - 1, n - 1);
  int k = VOL_sweepAtOrBelow(el);  // e_k <= el < e_{k+1}
  if (VOL_INTERPOLATION == 0) {
    // Nearest: the lower one on ties.
    int best = abs(el - VOL_sweepGeom[k + 1].x) < abs(el - VOL_sweepGeom[k].x) ? k + 1 : k;
    return ivec2(best, best);
  }
  t = (el - VOL_sweepGeom[k].x) / (VOL_sweepGeom[k + 1].x - VOL_sweepGeom[k].x);
  return ivec2(k, k + 1);
}

// The length of ray that crosses one cell here (volume::polarCellCrossingMeters, the same formula
// in float): the gate along the line from the antenna, the beam's width r x angle across it. An
// exaggerated volume's point is taken as it is drawn (its cells are as tall or taller there).
float VOL_cellCrossing(vec3 p, vec3 dir) {
  float r = length(p);
  if (VOL_cellScale.x <= 0.0 || r <= 0.0) return 0.0;
  float cosBeam = min(1.0, abs(dot(p, dir)) / r);
  float sinBeam = sqrt(max(0.0, 1.0 - cosBeam * cosBeam));
  return min(VOL_cellScale.x / max(cosBeam, 1e-6), r * VOL_cellScale.y / max(sinBeam, 1e-6));
}

// STATE_ECHO with its value, or STATE_NOT_ECHO (no echo or no data: the image treats both alike).

int VOL_sample(vec3 p, out float value) {
  value = 0.0;
  vec3 rae = VOL_antennaCoordinates(p);
  float t;
  ivec2 ks = VOL_bracket(rae.z, t);
  if (ks.x < 0) return STATE_NOT_ECHO;
  // Two calls always (a single sweep is the pair (k, k) with t = 0): one code path for all SIMD
  // lanes instead of one- and two-sweep branches that a mixed group would both run.
  float echoW = 0.0, sumV = 0.0;
  VOL_sampleSweep(ks.x, 1.0 - t, rae, echoW, sumV);
  VOL_sampleSweep(ks.y, t, rae, echoW, sumV);
  if (echoW >= 0.5) {
    value = sumV / echoW;
    return STATE_ECHO;
  }
  return STATE_NOT_ECHO;
}

// --- the ray interval: the clip sphere and the band of straight elevations ----------------
// sin(straight elevation) along the ray has at most one extremum, so the set where it lies in
// [sinLo, sinHi] is at most two intervals; breakpoints are roots of (u0 + t du)^2 = s^2 |p|^2
// (the cone of elevation asin(s) or its mirror). Up to two roots; a missing one is -1e30, which
// the caller clamps onto the span's start (an empty piece). No arrays: on llvmpipe a
// dynamically indexed array is a per-lane scatter/gather through memory, and the set-up written
// with arrays and an insertion sort cost more than the whole march on a top-down view.
vec2 VOL_coneRoots(vec3 o, vec3 d, float s) {
  float u0 = o.z, du = d.z;
  float A = du * du - s * s;  // |d| = 1
  float B = 2.0 * (u0 * du - s * s * dot(o, d));
  float C = u0 * u0 - s * s * dot(o, o);
  vec2 roots = vec2(-1e30);
  if (abs(A) < 1e-12) {
    if (abs(B) > 1e-12) roots.x = -C / B;
    return roots;
  }
  float disc = B * B - 4.0 * A * C;
  if (disc < 0.0) return roots;
  float sq = sqrt(disc);
  float q = -0.5 * (B + (B >= 0.0 ? sq : -sq));
  roots.x = q / A;
  if (q != 0.0) roots.y = C / q;
  return roots;
}

bool VOL_insideBand(vec3 p) {
  float r = length(p);
  if (r < 1e-3) return true;
  float s = p.z / r;
  return s >= VOL_straightElevationClipSin.x && s <= VOL_straightElevationClipSin.y;
}

// Widens [a, b] by the piece [p0, p1] of the ray if it lies inside the band.
void VOL_extendInBand(vec3 oL, vec3 dL, float p0, float p1, inout float a, inout float b) {
  if (p1 > p0 && VOL_insideBand(oL + 0.5 * (p0 + p1) * dL)) {
    a = min(a, p0);
    b = max(b, p1);
  }
}

// From the first piece of [span] inside the band to the end of the last one (x > y: none). The
// samples in a gap between two pieces (the cone of silence above the antenna) are outside every
// beam, so they add nothing, and the empty-space grid skips them. One interval, because
// llvmpipe runs a loop's whole body at least once even when no lane enters it: a loop per piece
// cost 7 ms of a 16-17 ms top-down frame (docs/bench-volume.md).
vec2 VOL_interval(vec3 eyeRel, vec3 dir, float tMax) {
  vec2 span = sphereInterval(eyeRel, dir, VOL_maxRange);
  span.x = max(span.x, 0.0);
  span.y = min(span.y, tMax);
  if (span.x >= span.y) return vec2(1.0, 0.0);
#if VOL_EXAGGERATED
  return span;
#endif
  // Split [span] at the band's boundaries (in the site's ENU frame): four cuts, clamped into the
  // span and put in order by a sorting network, give five pieces.
  vec3 oL = VOL_ecefToEnu * eyeRel, dL = VOL_ecefToEnu * dir;
  vec4 cuts = clamp(vec4(VOL_coneRoots(oL, dL, VOL_straightElevationClipSin.x), VOL_coneRoots(oL, dL, VOL_straightElevationClipSin.y)),
                    span.x, span.y);
  float c0 = cuts.x, c1 = cuts.y, c2 = cuts.z, c3 = cuts.w;
  orderPair(c0, c1);
  orderPair(c2, c3);
  orderPair(c0, c2);
  orderPair(c1, c3);
  orderPair(c1, c2);
  float a = 1e30, b = -1e30;
  VOL_extendInBand(oL, dL, span.x, c0, a, b);
  VOL_extendInBand(oL, dL, c0, c1, a, b);
  VOL_extendInBand(oL, dL, c1, c2, a, b);
  VOL_extendInBand(oL, dL, c2, c3, a, b);
  VOL_extendInBand(oL, dL, c3, span.y, a, b);
  return vec2(a, b);
}
