// Sampler of a radar network as one volume (spec: volume/RadarNetwork.h, the double-precision rule
// the CPU reference follows; engine/RadarNetworkGL.h packs the data), included once per network of
// a march with VOL_ replaced by its prefix (engine/VolumeGL.h).
//
// Positions are float32 relative to the network's origin (subtracted in double on the CPU). Each
// sample: the coverage index's cell from the direction of the point (geocentric latitude and
// longitude, as volume::CoverageIndex::cellOf), then only the radars that cell lists, each sampled
// by the rule of volume/PolarVolume.h in its own geometry (the beam model of polar_beam.glsl), and
// their values combined by the overlap rule. So a sample costs the radars over its place, not the
// radars of the network.
//
// Variant constants: VOL_INTERPOLATION (0 nearest, 1 linear), VOL_LISTED_UNROLLED (the most
// radars a coverage cell lists where that is at most RadarNetworkGL's kUnrolledListed, else 0: a
// loop of varying length), VOL_RULE (0 distance-weighted mean,
// 1 lowest beam, 2 maximum: volume::OverlapRule), VOL_EXAGGERATED (1: drawn at a vertical
// exaggeration, volume/VerticalExaggeration.h: each radar maps the point back to its true height on
// its own local sphere, as sample_polar.glsl does; the coverage cell is found at the point moved
// back along the ellipsoid's normal).
// @NEEDS polar_beam.glsl

// Per radar and sweep records, then the coverage index (RadarNetworkGL.cpp writes them): vec4s,
// so that a record is a few vector loads; the index's integers as floats (exact below 2^24).
layout(std430, binding = VOL_INDEX) readonly buffer VOL_NetworkData { vec4 VOL_data[]; };
uniform sampler2DArray VOL_values;  // RGBA16F, linear: sweeps as tiles side by side: (value if echo else 0, 1 if echo, 1 if measured)
uniform vec2 VOL_valuesInvSize;     // 1 / (layer width, height)
uniform float VOL_tileWidth;        // texels per tile (gates + 2: a padding column each side)
uniform int VOL_tilesPerLayer;
uniform sampler2D VOL_rayTable;     // R32F, linear: row g = sweep g's azimuth table; rows after the sweeps: each radar's elevation lookup
uniform float VOL_rayTableRows;
uniform int VOL_sweepBase;                // vec4 offset of the sweep records (radars start at 0)
uniform int VOL_cellBase, VOL_memberBase;  // float offsets (4 per vec4) of the cell starts and the members
uniform vec3 VOL_originEcef;        // the origin (float: only the coverage cell is found from it)
uniform vec4 VOL_coverage;          // latMinDeg, lonOriginDeg, cellDeg, -
uniform ivec2 VOL_coverageCells;    // columns, rows
uniform vec4 VOL_enclosing;         // centre (relative to the origin), radius: every radar's clip sphere
uniform vec4 VOL_top;               // the Earth's centre (relative to the origin), the radius above every beam
uniform float VOL_exaggeration;     // vertical exaggeration (1: none)

const int VOL_RADAR_VEC4S = 7;
// The mean rule's weights exp(-(r / L)^2) times exp(64) (they cancel in the mean): float holds
// them out to 700 km instead of 460 (exp(-86) is float's smallest normal).
const float VOL_WEIGHT_SHIFT = 64.0;
const float VOL_WEIGHT_LENGTH = 50000.0;  // volume::kMosaicWeightLengthMeters

// The i-th float of the buffer (the index's integers).
int VOL_int(int i) { return int(VOL_data[i >> 2][i & 3]); }
vec4 VOL_sweep(int g) { return VOL_data[VOL_sweepBase + 2 * g]; }  // elevationDeg, firstGateRange, gateSpacing, gateCount
float VOL_sweepRays(int g) { return VOL_data[VOL_sweepBase + 2 * g + 1].x; }

// The ray interval of a sphere, computed from the perpendicular part of the offset (float: the
// Earth's centre is 6400 km away) and widened by a margin that covers its rounding.
vec2 VOL_sphereInterval(vec3 o, vec3 d, float radius) {
  float b = dot(o, d);
  float perp = length(o - b * d);
  if (perp > radius) return vec2(1.0, 0.0);
  float sq = sqrt((radius - perp) * (radius + perp));
  float margin = 100.0 + 1e-6 * (abs(b) + radius);
  return vec2(-b - sq - margin, -b + sq + margin);
}

vec2 VOL_interval(vec3 eyeRel, vec3 dir, float tMax) {
  vec2 a = VOL_sphereInterval(eyeRel - VOL_enclosing.xyz, dir, VOL_enclosing.w);
  vec2 b = VOL_sphereInterval(eyeRel - VOL_top.xyz, dir, VOL_top.w);
  return vec2(max(max(a.x, b.x), 0.0), min(min(a.y, b.y), tMax));
}

// Sweep g's contribution with weight w: (sum of echo values, echo weight, measured weight).
void VOL_sampleSweep(int g, float w, vec3 rae, inout vec3 acc) {
  vec4 s = VOL_sweep(g);
  float gc = (rae.x - s.y) / s.z;
  if (gc < -0.5 || gc > s.w - 0.5) return;  // outside this sweep's gates: no data
  float n = VOL_sweepRays(g);
  float u = (rae.y * (float(RAY_TABLE_BINS) / 360.0) + 0.5) / float(RAY_TABLE_BINS + 1);
  float a = textureLod(VOL_rayTable, vec2(u, (float(g) + 0.5) / VOL_rayTableRows), 0.0).r;
  float y = a < 0.0 ? a + n : a;
  int layer = g / VOL_tilesPerLayer;
  float x0 = float(g - layer * VOL_tilesPerLayer) * VOL_tileWidth + 1.0;  // gate 0's column
  vec3 texel = textureLod(VOL_values, vec3((x0 + gc + 0.5) * VOL_valuesInvSize.x, (y + 0.5) * VOL_valuesInvSize.y,
                                           float(layer)), 0.0).rgb;
  acc += w * texel;
}

// Radar r's sample at p (relative to the origin): 2 echo (value), 1 no echo, 0 no data; its
// range and the height of its lowest beam over the point (the lowest-beam rule).
int VOL_sampleRadar(int r, vec3 p, out float value, out float rangeMeters, out float lowBeam) {
  value = 0.0;
  rangeMeters = 0.0;
  lowBeam = 0.0;
  int b = r * VOL_RADAR_VEC4S;
  vec4 site = VOL_data[b];  // site - origin, h0
  vec4 limits = VOL_data[b + 4];  // clip radius, half beam width, sweeps, first sweep
  vec3 d = p - site.xyz;
  vec4 east = VOL_data[b + 1], north = VOL_data[b + 2], up = VOL_data[b + 3];  // rows of ecefToEnu; M, N, Re
  float h0 = site.w, re = up.w;
#if VOL_EXAGGERATED
  vec3 l = polarUnexaggerateEnu(vec3(dot(east.xyz, d), dot(north.xyz, d), dot(up.xyz, d)), h0, east.w, north.w,
                                VOL_exaggeration);
  if (dot(l, l) > limits.x * limits.x) return 0;
#else
  if (dot(d, d) > limits.x * limits.x) return 0;
  vec3 l = vec3(dot(east.xyz, d), dot(north.xyz, d), dot(up.xyz, d));
#endif
  vec3 rae = polarAntennaCoordinatesEnu(l, h0, east.w, north.w, re, false);
  float hb = limits.y;
  int n = int(limits.z), g0 = int(limits.w);
  float e0 = VOL_sweep(g0).x, en = VOL_sweep(g0 + n - 1).x;
  float el = rae.z;
  if (el < e0 - hb || el > en + hb) return 0;
  // Bracket the elevation (PolarVolume.h, step 1).
  int k0 = 0, k1 = 0;
  float t = 0.0;
  if (el <= e0) {
    k0 = k1 = 0;
  } else if (el >= en) {
    k0 = k1 = n - 1;
  } else {
    vec4 lookup = VOL_data[b + 5];  // elevation range of the lookup, its row
    int bin = clamp(int((el - lookup.x) / (lookup.y - lookup.x) * float(ELEVATION_BINS)), 0, ELEVATION_BINS - 1);
    int k = int(texelFetch(VOL_rayTable, ivec2(bin, int(lookup.z)), 0).r);
    for (int it = 0; it < MAX_SWEEPS && k + 1 < n && VOL_sweep(g0 + k + 1).x <= el; ++it) ++k;
    float ek = VOL_sweep(g0 + k).x;
    float ek1 = VOL_sweep(g0 + k + 1).x;
    if (VOL_INTERPOLATION == 0) {
      k0 = k1 = abs(el - ek1) < abs(el - ek) ? k + 1 : k;
    } else {
      k0 = k;
      k1 = k + 1;
      t = (el - ek) / (ek1 - ek);
    }
  }
  vec3 acc = vec3(0.0);
  VOL_sampleSweep(g0 + k0, 1.0 - t, rae, acc);
  VOL_sampleSweep(g0 + k1, t, rae, acc);
  rangeMeters = rae.x;
  if (VOL_RULE == 1) {
    // The lowest sweep's beam centre over the point's ground distance s (RadarNetwork.h):
    // H - h0 = (re + h0) 2 sin(e0 + g / 2) sin(g / 2) / cos(e0 + g), g = s / re, without cancellation.
    float e0r = radians(e0);
    float elr = radians(el);
    float gam = atan(rae.x * cos(elr), rae.x * sin(elr) + re + h0);
    lowBeam = h0 + (re + h0) * 2.0 * sin(e0r + 0.5 * gam) * sin(0.5 * gam) / cos(min(e0r + gam, 1.5707));
  }
  if (acc.y >= 0.5) {
    value = acc.x / acc.y;
    return 2;
  }
  return acc.z >= 0.5 ? 1 : 0;
}

// The coverage cell of p, -1 outside the index.
int VOL_cellOf(vec3 p) {
  vec3 q = VOL_originEcef + p;
  float lon = degrees(atan(q.y, q.x));
  float lat = degrees(atan(q.z, length(q.xy)));
  float dl = lon - VOL_coverage.y;
  if (dl < 0.0) dl += 360.0;
  if (dl >= 360.0) dl -= 360.0;
  float x = dl / VOL_coverage.z, y = (lat - VOL_coverage.x) / VOL_coverage.z;
  if (!(x >= 0.0 && x < float(VOL_coverageCells.x) && y >= 0.0 && y < float(VOL_coverageCells.y))) return -1;
  return int(y) * VOL_coverageCells.x + int(x);
}

vec3 VOL_debugCoordinates(vec3 p) {
  int c = VOL_cellOf(p);
  return vec3(float(c), c < 0 ? 0.0 : float(VOL_int(VOL_cellBase + c + 1) - VOL_int(VOL_cellBase + c)), 0.0);
}

// The step rule (volume/StepRule.h; volume::RadarNetworkSampler::cellCrossingMeters): the
// smallest cell crossing (sample_polar.glsl's VOL_cellCrossing) of the radars the coverage cell
// lists whose clip sphere holds p; 0 (no rule: the fixed step) where none does.
float VOL_cellCrossing(vec3 p, vec3 dir) {
  int c = VOL_cellOf(p);
  if (c < 0) return 0.0;
  int first = VOL_int(VOL_cellBase + c), last = VOL_int(VOL_cellBase + c + 1);
  float best = 3.0e38;
#if VOL_LISTED_UNROLLED > 0
  for (int i = 0; i < VOL_LISTED_UNROLLED; ++i) {  // as in VOL_sample
    int j = first + i;
    if (j >= last) break;
#else
  for (int j = first; j < last; ++j) {
#endif
    int b = VOL_int(VOL_memberBase + j) * VOL_RADAR_VEC4S;
    vec3 d = p - VOL_data[b].xyz;
    float clip = VOL_data[b + 4].x;
    vec4 scale = VOL_data[b + 6];
    float rr = dot(d, d);
    if (rr <= clip * clip && rr > 0.0 && scale.x > 0.0 && scale.y > 0.0) {
      float r = sqrt(rr);
      float cosBeam = min(1.0, abs(dot(d, dir)) / r);
      float sinBeam = sqrt(max(0.0, 1.0 - cosBeam * cosBeam));
      best = min(best, min(scale.x / max(cosBeam, 1e-6), r * scale.y / max(sinBeam, 1e-6)));
    }
  }
  return best < 1.0e38 ? best : 0.0;
}

// The point drawn at p (relative to the origin) moved back to its true height along the
// ellipsoid's normal (volume::ExaggeratedSampler::trueEcef; the height from the geocentric radius,
// within metres of the geodetic one, which moves the point sideways by under 0.3 % of that):
// only to find its coverage cell, whose lists carry an 11 m margin.
vec3 VOL_trueForCell(vec3 p) {
#if VOL_EXAGGERATED
  const float a = WGS84_A;
  const float b = WGS84_A * (1.0 - WGS84_F);
  vec3 q = VOL_originEcef + p;
  float r = length(q);
  float s = q.z / r;
  float h = r - b / sqrt(1.0 - WGS84_E2 * (1.0 - s * s));
  vec3 n = normalize(vec3(q.x / a, q.y / a, q.z * a / (b * b)));
  return p - (1.0 - 1.0 / VOL_exaggeration) * h * n;
#else
  return p;
#endif
}

int VOL_sample(vec3 p, out float value) {
  value = 0.0;
  int c = VOL_cellOf(VOL_trueForCell(p));
  if (c < 0) return STATE_NOT_ECHO;
  int first = VOL_int(VOL_cellBase + c), last = VOL_int(VOL_cellBase + c + 1);
  float sumW = 0.0, echoW = 0.0, sumWV = 0.0;
  float best = -3.0e38, lowest = 3.0e38;
  bool echo = false;
  int lowestState = 0;
  float lowestValue = 0.0;
#if VOL_LISTED_UNROLLED > 0
  // Few radars over any cell (a lone radar's cluster): a loop of constant length, which the
  // compiler unrolls; a loop of varying length cost llvmpipe 1.45x (docs/networks.md).
  for (int i = 0; i < VOL_LISTED_UNROLLED; ++i) {
    int j = first + i;
    if (j >= last) break;
#else
  for (int j = first; j < last; ++j) {
#endif
    float v, r, low;
    int st = VOL_sampleRadar(VOL_int(VOL_memberBase + j), p, v, r, low);
    if (st == 0) continue;
    if (VOL_RULE == 0) {
      float q = r / VOL_WEIGHT_LENGTH;
      float w = exp(VOL_WEIGHT_SHIFT - q * q);
      sumW += w;
      if (st == 2) {
        echoW += w;
        sumWV += w * v;
        echo = true;
      }
    } else if (VOL_RULE == 1) {
      if (low < lowest) {
        lowest = low;
        lowestState = st;
        lowestValue = v;
      }
    } else if (st == 2 && v > best) {
      best = v;
      echo = true;
    }
  }
  if (VOL_RULE == 0) {
    if (echo && echoW >= 0.5 * sumW) {
      value = sumWV / echoW;
      return STATE_ECHO;
    }
  } else if (VOL_RULE == 1) {
    if (lowestState == 2) {
      value = lowestValue;
      return STATE_ECHO;
    }
  } else if (echo) {
    value = best;
    return STATE_ECHO;
  }
  return STATE_NOT_ECHO;
}
