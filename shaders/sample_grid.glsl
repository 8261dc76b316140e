// Sampler of a forecast grid in its own geometry (spec: volume/GridSampler.h; layout:
// engine/GridVolumeGL.h), included once per grid of a march with VOL_ replaced by that volume's
// prefix (engine/VolumeGL.h).
//
// Each sample: ECEF (float32: the origin plus the position) -> latitude, longitude, height
// (Bowring's formula) -> fractional column and row (lookup tables) -> the four columns around
// it -> the level: the cell's bracket of level pairs for the sample's height bin (one fetch,
// volume::GridLevelIndex), a bisection inside it (usually 0 or 1 steps) in the four columns'
// blended heights -> the value, linear in height between levels (or the nearest column and level).
//
// Variant constants: VOL_INTERPOLATION (0 nearest, 1 linear), VOL_CURVILINEAR (lookup by
// (latitude, longitude) instead of per axis), VOL_WRAPS (longitudes taken modulo 360 over the
// whole circle), VOL_REDUCED (a reduced grid: rows of different lengths; the row by the latitude
// table, in each of the two rows its own column from the row table). Injected: STATE_ECHO,
// STATE_NOT_ECHO, GPU_NO_DATA, GPU_NO_DATA_BELOW, WGS84_A, WGS84_F, WGS84_E2.

uniform sampler3D VOL_data;     // RG32F, texelFetch only: (value or GPU_NO_DATA, height above the ellipsoid m);
                                // after the levels (z >= VOL_texSize.z) the level brackets, 4 bins per texel
uniform sampler2D VOL_lookup;   // rectilinear R32F: row 0 longitude -> column, row 1 latitude -> row;
                                // curvilinear RG32F: (latitude, longitude) -> (column, row), -1e6 outside;
                                // reduced R32F: row 1 latitude -> row, and per closed row r at x = r:
                                // row 0 its closed columns, row 2 its first longitude, row 3 its spacing (deg);
                                // then (y = VOL_lookupSize.y, .r) the level map: reference level at equal heights
uniform vec3 VOL_origin;        // the volume's origin (ECEF m, narrowed)
uniform vec4 VOL_sphere;        // bounding sphere: centre relative to the origin, radius
uniform float VOL_outerRadius;  // a sphere about the Earth's centre holding the top level (m)
uniform vec2 VOL_heightRange;   // lowest and highest level height (m above the ellipsoid)
uniform vec4 VOL_lonLat;        // the tables' domains: longitude start, span, latitude start, span (deg);
                                // reduced: x, y the reference axis of the column index: west, spacing
uniform ivec2 VOL_lookupSize;
uniform ivec3 VOL_texSize;      // columns, rows, levels of VOL_data
uniform int VOL_rowOffset;      // 1 when row 0 is the south pole row
uniform vec4 VOL_reference;     // a reference latitude, longitude (deg) and their cos/sin packed: lat, lon, (unused)
uniform vec4 VOL_referenceTrig; // cos lat0, sin lat0, cos lon0, sin lon0
uniform vec4 VOL_levelMap;      // lowest height (m), (entries - 1) per metre, bins per reference level, bins
uniform vec4 VOL_cellScale;     // the step rule's (volume::CellScale): column spacing (m; 0: no rule), first
                                // height (m), entries per metre
uniform float VOL_levelSpacing[CELL_SCALE_ENTRIES];  // reference level spacing by height (m)
uniform vec4 VOL_hole;          // a latitude/longitude box with no data in this frame (engine::VolumeLayerGL::hole):
                                // west, span (deg; < 0: none), south, north

// In the hole (volume::LonLatBox::contains, the reference's volume::SamplerOutsideBox).
bool VOL_inHole(vec2 latLon) {
  return VOL_hole.y >= 0.0 && latLon.x >= VOL_hole.z && latLon.x <= VOL_hole.w &&
         (VOL_hole.y >= 360.0 || mod(latLon.y - VOL_hole.x, 360.0) <= VOL_hole.y);
}

// WGS84 geodetic latitude, longitude (deg) and height (m) of an ECEF point, Bowring's formula
// (one step from the parametric latitude). The angles come out of atan as small differences from
// a reference latitude/longitude (the grid's centre), then added to it: float atan is accurate
// relative to its result, so small angles keep metres where whole ones lose tens of metres.
vec3 VOL_geodetic(vec3 p) {
  const float a = WGS84_A;
  const float e2 = WGS84_E2;
  const float b = a * (1.0 - WGS84_F);  // a sqrt(1 - e2)
  const float ep2 = e2 / (1.0 - e2);
  vec3 e = VOL_origin + p;
  float rho = length(e.xy);
  float theta = atan(e.z * a, rho * b);
  float st = sin(theta), ct = cos(theta);
  float num = e.z + ep2 * b * st * st * st, den = rho - e2 * a * ct * ct * ct;
  vec4 r = VOL_referenceTrig;
  float dLat = atan(num * r.x - den * r.y, den * r.x + num * r.y);
  float dLon = atan(e.y * r.z - e.x * r.w, e.x * r.z + e.y * r.w);
  float lat = radians(VOL_reference.x) + dLat;
  float sl = sin(lat), cl = cos(lat);
  float h = rho * cl + e.z * sl - a * sqrt(1.0 - e2 * sl * sl);
  return vec3(VOL_reference.x + degrees(dLat), VOL_reference.y + degrees(dLon), h);
}

// The length of ray that crosses one cell here (volume::cellCrossingMeters, the same formula in
// float): the level spacing at the approximate height over |cos| of the angle with the
// geocentric vertical, or the column spacing over |sin| of it, the smaller.
float VOL_cellCrossing(vec3 p, vec3 dir) {
  const float b = WGS84_A * (1.0 - WGS84_F);
  vec3 e = VOL_origin + p;
  float r = length(e);
  float s = e.z / r;
  float h = r - b / sqrt(1.0 - WGS84_E2 * (1.0 - s * s));
  float cosUp = min(1.0, abs(dot(e, dir)) / r);
  float sinUp = sqrt(max(0.0, 1.0 - cosUp * cosUp));
  int i = int(clamp(floor((h - VOL_cellScale.y) * VOL_cellScale.z), 0.0, float(CELL_SCALE_ENTRIES - 1)));
  return min(VOL_levelSpacing[i] / max(cosUp, 1e-6), VOL_cellScale.x / max(sinUp, 1e-6));
}

// Fractional texture column and row of a latitude/longitude; false outside the grid.
bool VOL_columnRow(vec2 latLon, out vec2 ij) {
  ij = vec2(0.0);
  float lonOffset = mod(latLon.y - VOL_lonLat.x, 360.0);
#if VOL_CURVILINEAR
  vec2 x = vec2(lonOffset / VOL_lonLat.y, (latLon.x - VOL_lonLat.z) / VOL_lonLat.w) * vec2(VOL_lookupSize - 1);
  if (any(lessThan(x, vec2(0.0))) || any(greaterThan(x, vec2(VOL_lookupSize - 1)))) return false;
  ivec2 c = min(ivec2(floor(x)), VOL_lookupSize - 2);
  vec2 f = x - vec2(c);
  vec2 a00 = texelFetch(VOL_lookup, c, 0).rg, a10 = texelFetch(VOL_lookup, c + ivec2(1, 0), 0).rg;
  vec2 a01 = texelFetch(VOL_lookup, c + ivec2(0, 1), 0).rg, a11 = texelFetch(VOL_lookup, c + ivec2(1, 1), 0).rg;
  if (min(min(a00.x, a10.x), min(a01.x, a11.x)) < -0.5) return false;  // at the domain's edge
  ij = mix(mix(a00, a10, f.x), mix(a01, a11, f.x), f.y);
#else
#if VOL_WRAPS == 0
  if (lonOffset > VOL_lonLat.y) return false;
#endif
  float x = lonOffset / VOL_lonLat.y * float(VOL_lookupSize.x - 1);
  float y = (latLon.x - VOL_lonLat.z) / VOL_lonLat.w * float(VOL_lookupSize.x - 1);
  if (y < 0.0 || y > float(VOL_lookupSize.x - 1)) return false;
  int xi = min(int(x), VOL_lookupSize.x - 2), yi = min(int(y), VOL_lookupSize.x - 2);
  ij.x = mix(texelFetch(VOL_lookup, ivec2(xi, 0), 0).r, texelFetch(VOL_lookup, ivec2(xi + 1, 0), 0).r, x - float(xi));
  ij.y = mix(texelFetch(VOL_lookup, ivec2(yi, 1), 0).r, texelFetch(VOL_lookup, ivec2(yi + 1, 1), 0).r, y - float(yi));
#endif
  return true;
}

// The level pairs [x, y - 1] a sample at height z in the cell whose first column is `cell` can
// lie between (volume::GridLevelIndex: binOf and the packed brackets).
ivec2 VOL_levelBracket(ivec2 cell, float z) {
  float x = max(z - VOL_levelMap.x, 0.0) * VOL_levelMap.y;
  int e = min(int(x), VOL_lookupSize.x - 2);
  float ref = mix(texelFetch(VOL_lookup, ivec2(e, VOL_lookupSize.y), 0).r,
                  texelFetch(VOL_lookup, ivec2(e + 1, VOL_lookupSize.y), 0).r, clamp(x - float(e), 0.0, 1.0));
  int bin = clamp(int(floor(ref * VOL_levelMap.z)), 0, int(VOL_levelMap.w) - 1);
  vec2 t = texelFetch(VOL_data, ivec3(cell, VOL_texSize.z + bin / 4), 0).rg;
  int pair = int((bin & 2) == 0 ? t.x : t.y);
  int code = (bin & 1) == 0 ? (pair & 4095) : (pair >> 12);
  int lo = code & 255, span = code >> 8;
  return ivec2(lo, span >= 15 ? VOL_texSize.z - 1 : lo + span + 1);
}

#if VOL_REDUCED
// A reduced grid's corner and weights: row c.z at columns c.x, c.x + 1 (fraction f.x), row c.z + 1
// at columns c.y, c.y + 1 (fraction f.y), f.z between the rows.

// Row r's fractional column of a longitude from the row table: c, c + 1 (fraction f) within the
// row's closed columns; false when the row does not hold the longitude (a regional grid).
bool VOL_rowColumn(int r, float lon, out int c, out float f) {
  float n = texelFetch(VOL_lookup, ivec2(r, 0), 0).r;
  float first = texelFetch(VOL_lookup, ivec2(r, 2), 0).r, step = texelFetch(VOL_lookup, ivec2(r, 3), 0).r;
  float x = mod(lon - first, 360.0) / step;
  c = clamp(int(floor(x)), 0, max(int(n) - 2, 0));
  f = clamp(x - float(c), 0.0, 1.0);
  return x <= n - 1.0;
}

vec2 VOL_level(ivec3 c, vec3 f, int k) {
  vec2 d00 = texelFetch(VOL_data, ivec3(c.x, c.z, k), 0).rg, d10 = texelFetch(VOL_data, ivec3(c.x + 1, c.z, k), 0).rg;
  vec2 d01 = texelFetch(VOL_data, ivec3(c.y, c.z + 1, k), 0).rg, d11 = texelFetch(VOL_data, ivec3(c.y + 1, c.z + 1, k), 0).rg;
  // A corner of zero weight does not count, missing or not (as in the CPU rule).
  float w00 = (1.0 - f.x) * (1.0 - f.z), w10 = f.x * (1.0 - f.z), w01 = (1.0 - f.y) * f.z, w11 = f.y * f.z;
  bool missing = (w00 > 0.0 && d00.x < GPU_NO_DATA_BELOW) || (w10 > 0.0 && d10.x < GPU_NO_DATA_BELOW) ||
                 (w01 > 0.0 && d01.x < GPU_NO_DATA_BELOW) || (w11 > 0.0 && d11.x < GPU_NO_DATA_BELOW);
  vec2 blended = w00 * d00 + w10 * d10 + w01 * d01 + w11 * d11;
  return vec2(missing ? GPU_NO_DATA : blended.x, blended.y);
}

bool VOL_locate(vec3 p, out ivec3 c, out vec3 f, out int lo, out float fk, out vec2 levelLo, out vec2 levelHi) {
  levelLo = vec2(0.0);
  levelHi = vec2(0.0);
  c = ivec3(0);
  f = vec3(0.0);
  lo = 0;
  fk = 0.0;
  vec3 g = VOL_geodetic(p);
  if (g.z < VOL_heightRange.x || g.z > VOL_heightRange.y || VOL_inHole(g.xy)) return false;
  // The row as for a rectilinear grid.
  float y = (g.x - VOL_lonLat.z) / VOL_lonLat.w * float(VOL_lookupSize.x - 1);
  if (y < 0.0 || y > float(VOL_lookupSize.x - 1)) return false;
  int yi = min(int(y), VOL_lookupSize.x - 2);
  float row = mix(texelFetch(VOL_lookup, ivec2(yi, 1), 0).r, texelFetch(VOL_lookup, ivec2(yi + 1, 1), 0).r, y - float(yi));
  c.z = clamp(int(floor(row)), 0, VOL_texSize.y - 2);
  f.z = clamp(row - float(c.z), 0.0, 1.0);
  // Each row its own column; a row of positive weight must hold the longitude.
  bool in0 = VOL_rowColumn(c.z, g.y, c.x, f.x), in1 = VOL_rowColumn(c.z + 1, g.y, c.y, f.y);
  if ((f.z < 1.0 && !in0) || (f.z > 0.0 && !in1)) return false;
#if VOL_INTERPOLATION == 0
  // The column of largest weight alone (the CPU's rule): weights 0 or 1.
  float w00 = (1.0 - f.x) * (1.0 - f.z), w10 = f.x * (1.0 - f.z), w01 = (1.0 - f.y) * f.z, w11 = f.y * f.z;
  float best = max(max(w00, w10), max(w01, w11));
  if (w00 == best || w10 == best) {
    f = vec3(w00 == best ? 0.0 : 1.0, 0.0, 0.0);
  } else {
    f = vec3(0.0, w01 == best ? 0.0 : 1.0, 1.0);
  }
#endif
  ivec2 b0 = VOL_levelBracket(c.xz, g.z), b1 = VOL_levelBracket(ivec2(c.y, c.z + 1), g.z);
  lo = min(b0.x, b1.x);
  int hi = max(b0.y, b1.y);
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (VOL_level(c, f, mid).y <= g.z) lo = mid; else hi = mid;
  }
  levelLo = VOL_level(c, f, lo);
  levelHi = VOL_level(c, f, hi);
  // Below the lowest or above the highest level here (the brackets hold every height between).
  if (g.z < levelLo.y || g.z > levelHi.y) return false;
  fk = levelHi.y > levelLo.y ? clamp((g.z - levelLo.y) / (levelHi.y - levelLo.y), 0.0, 1.0) : 0.0;
  return true;
}

// (column on the reference axis, row, level): the column from the grid row of larger weight (a
// pole row has none: the other), its longitude back on the reference axis.
vec3 VOL_debugCoordinates(vec3 p) {
  ivec3 c;
  vec3 f;
  int lo;
  float fk;
  vec2 levelLo, levelHi;
  if (!VOL_locate(p, c, f, lo, fk, levelLo, levelHi)) return vec3(-1.0);
  int r = f.z < 0.5 ? c.z : c.z + 1;
  if (r < VOL_rowOffset || r >= VOL_texSize.y - VOL_rowOffset) r = r == c.z ? c.z + 1 : c.z;
  float column = r == c.z ? float(c.x) + f.x : float(c.y) + f.y;
  float lon = texelFetch(VOL_lookup, ivec2(r, 2), 0).r + column * texelFetch(VOL_lookup, ivec2(r, 3), 0).r;
  return vec3(mod(lon - VOL_lonLat.x, 360.0) / VOL_lonLat.y, float(c.z) + f.z - float(VOL_rowOffset), float(lo) + fk);
}

int VOL_sample(vec3 p, out float value) {
  value = 0.0;
  ivec3 c;
  vec3 f;
  int lo;
  float fk;
  vec2 levelLo, levelHi;
  if (!VOL_locate(p, c, f, lo, fk, levelLo, levelHi)) return STATE_NOT_ECHO;
#if VOL_INTERPOLATION == 0
  float v = fk < 0.5 ? levelLo.x : levelHi.x;
#else
  float a = levelLo.x, b = levelHi.x;
  float v = (a < GPU_NO_DATA_BELOW || b < GPU_NO_DATA_BELOW) ? GPU_NO_DATA : mix(a, b, fk);
#endif
  if (v < GPU_NO_DATA_BELOW) return STATE_NOT_ECHO;
  value = v;
  return STATE_ECHO;
}

#else
// Level k at the four columns, blended: (value or GPU_NO_DATA when any is missing, height).
vec2 VOL_level(ivec2 c, vec2 f, int k) {
  vec2 d00 = texelFetch(VOL_data, ivec3(c, k), 0).rg, d10 = texelFetch(VOL_data, ivec3(c + ivec2(1, 0), k), 0).rg;
  vec2 d01 = texelFetch(VOL_data, ivec3(c + ivec2(0, 1), k), 0).rg, d11 = texelFetch(VOL_data, ivec3(c + ivec2(1, 1), k), 0).rg;
  // A corner of zero weight does not count, missing or not (as in the CPU rule).
  float w00 = (1.0 - f.x) * (1.0 - f.y), w10 = f.x * (1.0 - f.y), w01 = (1.0 - f.x) * f.y, w11 = f.x * f.y;
  bool missing = (w00 > 0.0 && d00.x < GPU_NO_DATA_BELOW) || (w10 > 0.0 && d10.x < GPU_NO_DATA_BELOW) ||
                 (w01 > 0.0 && d01.x < GPU_NO_DATA_BELOW) || (w11 > 0.0 && d11.x < GPU_NO_DATA_BELOW);
  vec2 blended = w00 * d00 + w10 * d10 + w01 * d01 + w11 * d11;
  return vec2(missing ? GPU_NO_DATA : blended.x, blended.y);
}

// Fractional (column, row, level) of p, the columns' corner and weights, the blended (value,
// height) of the levels below and above; false where there is no data for lack of a position.
bool VOL_locate(vec3 p, out ivec2 c, out vec2 f, out int lo, out float fk, out vec2 levelLo, out vec2 levelHi) {
  levelLo = vec2(0.0);
  levelHi = vec2(0.0);
  c = ivec2(0);
  f = vec2(0.0);
  lo = 0;
  fk = 0.0;
  vec3 g = VOL_geodetic(p);
  if (g.z < VOL_heightRange.x || g.z > VOL_heightRange.y || VOL_inHole(g.xy)) return false;
  vec2 ij;
  if (!VOL_columnRow(g.xy, ij)) return false;
  c = clamp(ivec2(floor(ij)), ivec2(0), VOL_texSize.xy - 2);
  f = clamp(ij - vec2(c), 0.0, 1.0);
#if VOL_INTERPOLATION == 0
  c += ivec2(greaterThan(f, vec2(0.5)));
  c = min(c, VOL_texSize.xy - 1);
  // The nearest column alone: blend with weight 0 on the next one (kept inside the texture).
  ivec2 shift = ivec2(greaterThanEqual(c, VOL_texSize.xy - 1));
  f = vec2(shift);
  c -= shift;
#endif
  ivec2 bracket = VOL_levelBracket(c, g.z);
  lo = bracket.x;
  int hi = bracket.y;
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (VOL_level(c, f, mid).y <= g.z) lo = mid; else hi = mid;
  }
  levelLo = VOL_level(c, f, lo);
  levelHi = VOL_level(c, f, hi);
  // Below the lowest or above the highest level here (the brackets hold every height between).
  if (g.z < levelLo.y || g.z > levelHi.y) return false;
  fk = levelHi.y > levelLo.y ? clamp((g.z - levelLo.y) / (levelHi.y - levelLo.y), 0.0, 1.0) : 0.0;
  return true;
}

vec3 VOL_debugCoordinates(vec3 p) {
  ivec2 c;
  vec2 f;
  int lo;
  float fk;
  vec2 levelLo, levelHi;
  if (!VOL_locate(p, c, f, lo, fk, levelLo, levelHi)) return vec3(-1.0);
  return vec3(vec2(c) + f - vec2(0.0, float(VOL_rowOffset)), float(lo) + fk);
}

int VOL_sample(vec3 p, out float value) {
  value = 0.0;
  ivec2 c;
  vec2 f;
  int lo;
  float fk;
  vec2 levelLo, levelHi;
  if (!VOL_locate(p, c, f, lo, fk, levelLo, levelHi)) return STATE_NOT_ECHO;
#if VOL_INTERPOLATION == 0
  float v = fk < 0.5 ? levelLo.x : levelHi.x;
#else
  float a = levelLo.x, b = levelHi.x;
  float v = (a < GPU_NO_DATA_BELOW || b < GPU_NO_DATA_BELOW) ? GPU_NO_DATA : mix(a, b, fk);
#endif
  if (v < GPU_NO_DATA_BELOW) return STATE_NOT_ECHO;
  value = v;
  return STATE_ECHO;
}
#endif

vec2 VOL_interval(vec3 eyeRel, vec3 dir, float tMax) {
  vec2 a = sphereInterval(eyeRel - VOL_sphere.xyz, dir, VOL_sphere.w);
  vec2 b = sphereInterval(eyeRel + VOL_origin, dir, VOL_outerRadius);
  return vec2(max(max(a.x, b.x), 0.0), min(min(a.y, b.y), tMax));
}
