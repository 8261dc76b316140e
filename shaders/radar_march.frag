// Ray marcher for radar volumes in their own polar geometry (spec: volume/PolarVolume.h).
//
// Positions are float32 relative to the antenna (site ECEF subtracted in double on the CPU).
// Each sample: site-relative ECEF -> (range, azimuth, elevation) by the beam model, then the
// sampling rule of PolarVolume.h (sweeps bracketing the elevation, rays by azimuth, gates by
// range; nearest or linear), then the transfer function. Samples sit at t_i = (i + 0.5) * step
// from the eye (the same positions as the CPU reference), only inside the volume's shell:
// the max-range sphere and the band of straight elevations that contains every beam
// (widened by the beam's bending), and before the globe's depth.
#define MAX_SWEEPS 32
#define RAY_TABLE_BINS 8192
#define ELEVATION_BINS 2048
#define GRID_BLOCK 8

in vec2 v_uv;

// Variant constants: one program per combination, compiled on first use
// (RadarVolumeRendererGL::marchProgram). On llvmpipe, branches on uniforms cost as much as
// running both sides, so specialising them away is 1.6-1.8x faster (docs/bench-volume.md).
#ifndef MARCH_MODE
#define MARCH_MODE 0
#endif
#ifndef MARCH_INTERPOLATION
#define MARCH_INTERPOLATION 1
#endif
#ifndef MARCH_BEAM
#define MARCH_BEAM 0
#endif
#ifndef MARCH_SKIP_EMPTY
#define MARCH_SKIP_EMPTY 1
#endif
#ifndef MARCH_PREINTEGRATED
#define MARCH_PREINTEGRATED 0
#endif
const int kMode = MARCH_MODE;                    // 0 DVR, 1 MIP, 2 isosurface, 3 debug: antenna coordinates at u_debugT
const int kInterpolation = MARCH_INTERPOLATION;  // 0 nearest, 1 linear
const int kBeamModel = MARCH_BEAM;               // 0: effective-Earth (4/3) on the local sphere, 1: straight lines
const int kSkipEmpty = MARCH_SKIP_EMPTY;         // 1: jump over cells of the empty-space grid that cannot contribute
const int kPreintegrated = MARCH_PREINTEGRATED;  // DVR only. 0: each sample classified alone (post-classification);
                                                 // 1: each pair of neighbouring samples as a linear segment (u_tfIntegral)


uniform sampler2DArray u_values;    // RG16F, linear (nearest sampler for nearest interpolation): [sweep] (rays + 1) x (gates + 1): (value if echo else 0, 1 if echo else 0)
uniform vec2 u_valuesInvSize;       // 1 / (gates + 1, rays + 1) of a layer
uniform sampler1DArray u_rayTable;  // R32F, linear: [sweep] ray coordinate at azimuth j * 360 / RAY_TABLE_BINS
uniform isampler2D u_elLookup;      // R32I, ELEVATION_BINS x 1: last sweep with elevation <= bin start, -1 none
uniform vec2 u_elLookupRange;       // elevations (deg) of the table's first bin start and last bin end
uniform sampler3D u_grid;           // R16F: per cell of a box in the site's ENU frame, the largest value a sample there can see
uniform sampler3D u_gridBlocks;     // R16F: the same per block of GRID_BLOCK^3 cells
uniform sampler2D u_transfer;       // RGBA32F, 4096 x 1: classify() over [u_tfRange.x, u_tfRange.y]; DVR: alpha per step,
                                    // pre-integrated DVR: (rgb, extinction per metre)
uniform sampler2D u_tfIntegral;     // RGBA32F, (4096 + 1) x 1, linear: volume::transferIntegralTable over u_tfRange
uniform sampler2D u_globeDepth;     // reverse-Z depth of the globe pass (full resolution)

uniform vec4 u_sweepGeom[MAX_SWEEPS];  // elevationDeg, firstGateRange, gateSpacing, gateCount
uniform int u_sweepRays[MAX_SWEEPS];
uniform int u_sweepCount;
uniform float u_halfBeamDeg;
uniform float u_maxRange;
uniform vec2 u_straightElevationClipSin;  // sin of the straight-line elevation band that holds every beam
uniform vec3 u_gridMinEnu;                 // the grid box's lower corner (m, ENU)
uniform vec3 u_gridCellSize;               // (m)
uniform ivec3 u_gridCells;

uniform mat3 u_ecefToEnu;    // rows: east, north, up at the site
uniform float u_h0;          // antenna height above the ellipsoid (m)
uniform float u_meridionalRadius;  // M at the site (m)
uniform float u_primeVerticalRadius;  // N at the site (m)
uniform float u_effectiveRadius;   // Re = ke * R (m)

uniform vec3 u_eyeRelSite;         // eye - site, ECEF (m), from double
uniform mat3 u_cameraToEcef;
uniform float u_focalPx;           // of the full-resolution image
uniform vec2 u_imageSizePx;        // full resolution
uniform float u_near;

uniform float u_step;
uniform vec2 u_tfRange;
uniform float u_isoValue;
uniform float u_earlyTermination;
uniform float u_opacityZeroValue;
uniform float u_debugT;
uniform float u_mipVisibleMin;

layout(location = 0) out vec4 o_color;

const int NOT_ECHO = 0;
const int ECHO = 1;

// --- geometry: site-relative ECEF -> (range m, azimuth deg, elevation deg) ---------------
vec3 antennaCoordinates(vec3 p) {
  vec3 l = u_ecefToEnu * p;  // east, north, up
  float dh = length(l.xy);
  float az = degrees(atan(l.x, l.y));
  if (az < 0.0) az += 360.0;
  if (kBeamModel == 1) {
    float r = length(l);
    return vec3(r, az, degrees(asin(clamp(l.z / max(r, 1e-6), -1.0, 1.0))));
  }
  // Local sphere with the ellipsoid's normal-section radius in this azimuth (Euler).
  float ca = dh > 0.0 ? l.y / dh : 1.0, sa = dh > 0.0 ? l.x / dh : 0.0;
  float rAlpha = 1.0 / (ca * ca / u_meridionalRadius + sa * sa / u_primeVerticalRadius);
  float rc = rAlpha + u_h0;
  float w = l.z + rc;
  float dl = sqrt(dh * dh + w * w);
  float h = u_h0 + (dh * dh + l.z * l.z + 2.0 * l.z * rc) / (dl + rc);  // |d| - rc without cancellation
  float s = rAlpha * atan(dh, w);
  // Effective-Earth beam inverse (REFERENCE §2) in the cancellation-free form.
  float re = u_effectiveRadius;
  float gamma = s / re;
  float rho1 = re + u_h0, rho2 = re + h;
  float sg = sin(0.5 * gamma);
  float dz = h - u_h0;
  float r = sqrt(dz * dz + 4.0 * rho1 * rho2 * sg * sg);
  float el = degrees(atan(dz - 2.0 * rho2 * sg * sg, rho2 * sin(gamma)));
  return vec3(r, az, el);
}

// --- the sampling rule (PolarVolume.h) ---------------------------------------------------
// Ray coordinate in [-1, n): the sweep's table interpolated linearly (volume::rayCoordinateTable;
// below 0 it lies between the last ray and ray 0).
float rayCoordinate(int k, float az) {
  float u = (az * (float(RAY_TABLE_BINS) / 360.0) + 0.5) / float(RAY_TABLE_BINS + 1);
  return textureLod(u_rayTable, vec2(u, float(k)), 0.0).r;
}

// Adds sweep k's contribution with weight w: echo weight and weighted sum of echo values.
void sampleSweep(int k, float w, vec3 rae, inout float echoW, inout float sumV) {
  vec4 g = u_sweepGeom[k];
  float gc = (rae.x - g.y) / g.z;
  if (gc < -0.5 || gc > g.w - 0.5) return;  // outside this sweep's gates: no data
  int n = u_sweepRays[k];
  // One fetch: bilinear over (gate, ray) with the linear filter, or the nearest texel (round)
  // when the host binds a nearest sampler; row n repeats ray 0, column gateCount the last gate.
  float a = rayCoordinate(k, rae.y);
  float y = a < 0.0 ? a + float(n) : a;
  vec2 texel = textureLod(u_values, vec3((gc + 0.5) * u_valuesInvSize.x, (y + 0.5) * u_valuesInvSize.y, float(k)), 0.0).rg;
  sumV += w * texel.x;
  echoW += w * texel.y;
}

// Brackets the elevation: sweeps (k0, k1) with weights (1 - t, t); k0 < 0: outside.
// The elevation lookup table gives the last sweep at or below the bin's start; at most a
// few sweeps can start inside one bin, so the scan after it is short.
int sweepAtOrBelow(float el) {
  int n = u_sweepCount;
  int bin = clamp(int((el - u_elLookupRange.x) / (u_elLookupRange.y - u_elLookupRange.x) * float(ELEVATION_BINS)), 0,
                  ELEVATION_BINS - 1);
  int k = texelFetch(u_elLookup, ivec2(bin, 0), 0).r;
  for (int it = 0; it < MAX_SWEEPS && k + 1 < n && u_sweepGeom[k + 1].x <= el; ++it) ++k;
  return k;
}

ivec2 bracket(float el, out float t) {
  t = 0.0;
  int n = u_sweepCount;
  float e0 = u_sweepGeom[0].x, en = u_sweepGeom[n - 1].x;
  if (el < e0 - u_halfBeamDeg || el > en + u_halfBeamDeg) return ivec2(-1);
  if (el <= e0) return ivec2(0, 0);
  if (el >= en) return ivec2(n - 1, n - 1);
  int k = sweepAtOrBelow(el);  // e_k <= el < e_{k+1}
  if (kInterpolation == 0) {
    // Nearest: the lower one on ties.
    int best = abs(el - u_sweepGeom[k + 1].x) < abs(el - u_sweepGeom[k].x) ? k + 1 : k;
    return ivec2(best, best);
  }
  t = (el - u_sweepGeom[k].x) / (u_sweepGeom[k + 1].x - u_sweepGeom[k].x);
  return ivec2(k, k + 1);
}

// ECHO with its value, or NOT_ECHO (no echo or no data: the image treats both alike).
int samplePolar(vec3 rae, out float value) {
  value = 0.0;
  float t;
  ivec2 ks = bracket(rae.z, t);
  if (ks.x < 0) return NOT_ECHO;
  // Two calls always (a single sweep is the pair (k, k) with t = 0): one code path for all SIMD
  // lanes instead of one- and two-sweep branches that a mixed group would both run.
  float echoW = 0.0, sumV = 0.0;
  sampleSweep(ks.x, 1.0 - t, rae, echoW, sumV);
  sampleSweep(ks.y, t, rae, echoW, sumV);
  if (echoW >= 0.5) {
    value = sumV / echoW;
    return ECHO;
  }
  return NOT_ECHO;
}

// Empty-space skipping: the largest value any sample in this grid cell can see, and the
// ray parameter where the ray leaves the cell (slab method in ENU).
float gridMax(vec3 l, out ivec3 cell) {
  cell = ivec3(floor((l - u_gridMinEnu) / u_gridCellSize));
  if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, u_gridCells))) return -1e30;
  return texelFetch(u_grid, cell, 0).r;
}

// The ray's parameter interval inside the grid box (empty: x > y).
vec2 gridBoxInterval(vec3 oL, vec3 dL) {
  vec3 lo = u_gridMinEnu, hi = u_gridMinEnu + vec3(u_gridCells) * u_gridCellSize;
  vec3 inv = 1.0 / dL;
  vec3 t0 = (lo - oL) * inv, t1 = (hi - oL) * inv;
  float tNear = max(max(min(t0.x, t1.x), min(t0.y, t1.y)), min(t0.z, t1.z));
  float tFar = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z));
  return vec2(tNear, tFar);
}

// Where the ray leaves the box of `size` cells starting at cell `cell`.
float cellExit(vec3 oL, vec3 dL, ivec3 cell, float size) {
  vec3 lo = u_gridMinEnu + vec3(cell) * u_gridCellSize;
  vec3 hi = lo + size * u_gridCellSize;
  vec3 inv = 1.0 / dL;
  vec3 t0 = (lo - oL) * inv, t1 = (hi - oL) * inv;
  vec3 tFar = max(t0, t1);
  return min(tFar.x, min(tFar.y, tFar.z));
}

vec4 classify(float v) {
  float x = (v - u_tfRange.x) / (u_tfRange.y - u_tfRange.x);
  int i = clamp(int(x * 4096.0), 0, 4095);
  return texelFetch(u_transfer, ivec2(i, 0), 0);
}

// Pre-integrated classification (volume::transferIntegralTable): the cumulative integrals
// (of extinction * colour, of extinction) at a value, interpolated linearly between bin edges.
vec4 tfIntegral(float v) {
  float x = (v - u_tfRange.x) / (u_tfRange.y - u_tfRange.x) * 4096.0;
  return textureLod(u_tfIntegral, vec2((x + 0.5) / 4097.0, 0.5), 0.0);
}

// Premultiplied colour and opacity of a path of `lengthMeters` with constant classification
// c = (rgb, extinction per metre).
vec4 constantPath(vec4 c, float lengthMeters) {
  float alpha = 1.0 - exp(-c.a * lengthMeters);
  return vec4(c.rgb * alpha, alpha);
}

// The same for one step along which the value goes linearly from v0 (front) to v1 (back):
// exact optical depth from the integral table; colour = the extinction-weighted mean colour
// times the opacity. Below a change of 1e-4 of the table's value range (0.013 dBZ for
// reflectivity) the table's difference quotient loses float precision (its integrals carry a
// relative error of ~1e-7 of the whole range), and the path is taken as the mean of its ends'
// classifications.
vec4 linearPath(float v0, vec4 i0, vec4 c0, float v1, vec4 i1, vec4 c1) {
  float dv = v1 - v0;
  vec3 emission;
  float tau;
  if (abs(dv) > 1e-4 * (u_tfRange.y - u_tfRange.x)) {
    tau = u_step * (i1.a - i0.a) / dv;
    emission = u_step * (i1.rgb - i0.rgb) / dv;
  } else {
    tau = u_step * 0.5 * (c0.a + c1.a);
    emission = u_step * 0.5 * (c0.rgb * c0.a + c1.rgb * c1.a);
  }
  tau = max(tau, 0.0);
  float alpha = 1.0 - exp(-tau);
  return vec4(tau > 1e-9 ? emission * (alpha / tau) : emission, alpha);
}

void composite(inout vec4 acc, vec4 premultiplied) {
  acc.rgb += (1.0 - acc.a) * premultiplied.rgb;
  acc.a += (1.0 - acc.a) * premultiplied.a;
}

// --- clipping: ray vs sphere and the band of straight elevations --------------------------
vec2 sphereInterval(vec3 o, vec3 d, float radius) {
  float b = dot(o, d);
  float c = dot(o, o) - radius * radius;
  float disc = b * b - c;
  if (disc < 0.0) return vec2(1.0, 0.0);
  float sq = sqrt(disc);
  return vec2(-b - sq, -b + sq);
}

// sin(straight elevation) along the ray has at most one extremum, so the set where it lies in
// [sinLo, sinHi] is at most two intervals; breakpoints are roots of (u0 + t du)^2 = s^2 |p|^2
// (the cone of elevation asin(s) or its mirror). Up to two roots; a missing one is -1e30, which
// the caller clamps onto the span's start (an empty piece). No arrays: on llvmpipe a
// dynamically indexed array is a per-lane scatter/gather through memory, and the set-up written
// with arrays and an insertion sort cost more than the whole march on a top-down view.
vec2 coneRoots(vec3 o, vec3 d, float s) {
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

void orderPair(inout float a, inout float b) {
  float lo = min(a, b);
  b = max(a, b);
  a = lo;
}

bool insideBand(vec3 p) {
  float r = length(p);
  if (r < 1e-3) return true;
  float s = p.z / r;
  return s >= u_straightElevationClipSin.x && s <= u_straightElevationClipSin.y;
}

// Widens [a, b] by the piece [p0, p1] of the ray if it lies inside the band.
void extendInBand(vec3 oL, vec3 dL, float p0, float p1, inout float a, inout float b) {
  if (p1 > p0 && insideBand(oL + 0.5 * (p0 + p1) * dL)) {
    a = min(a, p0);
    b = max(b, p1);
  }
}

void main() {
  vec2 pixel = vec2(v_uv.x * u_imageSizePx.x, (1.0 - v_uv.y) * u_imageSizePx.y);  // from the top
  vec3 dirEye = vec3((pixel.x - 0.5 * u_imageSizePx.x) / u_focalPx, (0.5 * u_imageSizePx.y - pixel.y) / u_focalPx, -1.0);
  vec3 dir = normalize(u_cameraToEcef * dirEye);

  if (kMode == 3) {
    o_color = vec4(antennaCoordinates(u_eyeRelSite + u_debugT * dir), 1.0);
    return;
  }

  // The globe hides what is behind it: reverse-Z depth = near / view distance.
  float depth = textureLod(u_globeDepth, v_uv, 0.0).r;
  float tGround = depth > 0.0 ? (u_near / depth) / (-dirEye.z / length(dirEye)) : 1e30;

  vec2 span = sphereInterval(u_eyeRelSite, dir, u_maxRange);
  span.x = max(span.x, 0.0);
  span.y = min(span.y, tGround);
  o_color = vec4(0.0);
  if (span.x >= span.y) return;

  // Split [span] at the elevation-band boundaries (in the site's ENU frame): four cuts, clamped
  // into the span and put in order by a sorting network, give five pieces.
  vec3 oL = u_ecefToEnu * u_eyeRelSite, dL = u_ecefToEnu * dir;
  vec4 cuts = clamp(vec4(coneRoots(oL, dL, u_straightElevationClipSin.x), coneRoots(oL, dL, u_straightElevationClipSin.y)),
                    span.x, span.y);
  float c0 = cuts.x, c1 = cuts.y, c2 = cuts.z, c3 = cuts.w;
  orderPair(c0, c1);
  orderPair(c2, c3);
  orderPair(c0, c2);
  orderPair(c1, c3);
  orderPair(c1, c2);
  // Outside the grid's box every sample is empty (the box holds every measured gate's support):
  // with skipping on, march only across the box.
  vec2 box = kSkipEmpty == 1 ? gridBoxInterval(oL, dL) : vec2(-1e30, 1e30);

  vec4 acc = vec4(0.0);
  // Pre-integrated DVR: the last sample taken (index, echo, value, integrals, classification).
  // A run of echo samples i..j stands for the path from t_i - step/2 to t_j + step/2, like the
  // post-classified samples it replaces: half a step of constant classification at each end,
  // a linear segment between neighbours.
  int prevIndex = -2;
  bool prevEcho = false;
  float prevV = 0.0;
  vec4 prevIntegral = vec4(0.0), prevC = vec4(0.0);
  float maxValue = -1e30;
  bool hit = false;
  float hitT = 0.0;
  // March from the first piece inside the band to the end of the last one, in one loop: the
  // samples in a gap between two pieces (the cone of silence above the antenna) are outside
  // every beam, so they add nothing, and the empty-space grid skips them. One loop, because
  // llvmpipe runs a loop's whole body at least once even when no lane enters it: a loop per
  // piece cost 7 ms of a 16-17 ms top-down frame (docs/bench-volume.md).
  float a = 1e30, b = -1e30;
  extendInBand(oL, dL, span.x, c0, a, b);
  extendInBand(oL, dL, c0, c1, a, b);
  extendInBand(oL, dL, c1, c2, a, b);
  extendInBand(oL, dL, c2, c3, a, b);
  extendInBand(oL, dL, c3, span.y, a, b);
  a = max(a, box.x);
  b = min(b, box.y);
  if (a <= b) {
    int i = int(ceil(a / u_step - 0.5));
    int iEnd = int(floor(b / u_step - 0.5));
    for (; i <= iEnd; ++i) {
      if (kSkipEmpty == 1) {
        // While nothing in the sample's cell can change the result (DVR: nothing above the
        // zero-opacity value; MIP: nothing above the maximum so far or the first visible
        // colour; isosurface: nothing at or above the iso value), jump to the first sample
        // after the cell, staying on the t_i grid. An inner loop, so that on SIMD hardware
        // the lanes of a group skip together and then sample together (one loop doing either
        // per iteration pays for both whenever the lanes disagree).
        float threshold = kMode == 0 ? u_opacityZeroValue : (kMode == 1 ? max(maxValue, u_mipVisibleMin) : u_isoValue);
        while (i <= iEnd) {
          float ts = (float(i) + 0.5) * u_step;
          ivec3 cell;
          float tOut;
          if (gridMax(oL + ts * dL, cell) >= threshold) break;
          bool outside = any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, u_gridCells));
          if (outside) {
            // Where the ray next enters the box after ts (b if it never does).
            tOut = box.x > box.y || box.y < ts ? b : max(box.x, ts);
          } else {
            // A whole block below the threshold: leave the block, not just the cell.
            ivec3 block = cell / GRID_BLOCK;
            tOut = texelFetch(u_gridBlocks, block, 0).r < threshold ? cellExit(oL, dL, block * GRID_BLOCK, float(GRID_BLOCK))
                                                                    : cellExit(oL, dL, cell, 1.0);
          }
          if (!(tOut > ts)) tOut = ts;  // degenerate slab (NaN): no jump
          i = max(i + 1, int(ceil(tOut / u_step - 0.5)));
        }
        if (i > iEnd) break;
      }
      float t = (float(i) + 0.5) * u_step;
      vec3 rae = antennaCoordinates(u_eyeRelSite + t * dir);
      float v;
      int state = samplePolar(rae, v);
      if (kMode == 0 && kPreintegrated == 1) {
        // A run is made of echo samples above the zero-opacity value: the samples the empty-space
        // grid may skip are all at or below it, so the runs, and the picture, do not depend on
        // whether skipping is on.
        bool echo = state == ECHO && v > u_opacityZeroValue;
        vec4 c = classify(v);
        vec4 integral = tfIntegral(v);
        bool adjacent = prevEcho && echo && i == prevIndex + 1;
        // A run ends (this sample is not echo, or empty cells were skipped since the last one):
        // the last sample's half step.
        if (prevEcho && !adjacent) composite(acc, constantPath(prevC, 0.5 * u_step));
        if (echo) composite(acc, adjacent ? linearPath(prevV, prevIntegral, prevC, v, integral, c) : constantPath(c, 0.5 * u_step));
        prevIndex = i;
        prevEcho = echo;
        prevV = v;
        prevIntegral = integral;
        prevC = c;
        if (acc.a >= u_earlyTermination) break;
      } else if (kMode == 0) {
        if (state != ECHO) continue;
        vec4 c = classify(v);  // alpha corrected for the step length on the CPU (setUniforms)
        composite(acc, vec4(c.a * c.rgb, c.a));
        if (acc.a >= u_earlyTermination) break;
      } else if (kMode == 1) {
        if (state == ECHO) maxValue = max(maxValue, v);
      } else if (kMode == 2) {
        float vv = state == ECHO ? v : -1e30;
        if (vv >= u_isoValue) {
          // Bisection between the previous sample position and this one.
          float lo = t - u_step, hi = t;
          for (int it = 0; it < 8; ++it) {
            float mid = 0.5 * (lo + hi);
            float vm;
            int sm = samplePolar(antennaCoordinates(u_eyeRelSite + mid * dir), vm);
            if (sm == ECHO && vm >= u_isoValue) hi = mid; else lo = mid;
          }
          hitT = hi;
          hit = true;
          break;
        }
      }
    }
  }

  if (kMode == 0) {
    if (kPreintegrated == 1 && prevEcho && acc.a < u_earlyTermination) composite(acc, constantPath(prevC, 0.5 * u_step));
    o_color = acc;
  } else if (kMode == 1) {
    if (maxValue > -1e29) {
      vec4 c = classify(maxValue);
      o_color = vec4(c.rgb * c.a, c.a);
    }
  } else if (kMode == 2 && hit) {
    vec3 p = u_eyeRelSite + hitT * dir;
    float h = 0.5 * u_step;
    vec3 grad;
    for (int axis = 0; axis < 3; ++axis) {
      vec3 e = vec3(0.0);
      e[axis] = h;
      float vp, vm;
      int sp = samplePolar(antennaCoordinates(p + e), vp);
      int sm = samplePolar(antennaCoordinates(p - e), vm);
      if (sp != ECHO) vp = u_opacityZeroValue;
      if (sm != ECHO) vm = u_opacityZeroValue;
      grad[axis] = (vp - vm) / (2.0 * h);
    }
    vec3 n = length(grad) > 0.0 ? -normalize(grad) : -dir;
    vec4 c = classify(u_isoValue);
    o_color = vec4(c.rgb * (0.3 + 0.7 * abs(dot(n, dir))), 1.0);
  }
}
