// The far field of a volume (engine/FarFieldGL.h; docs/networks.md, "The far field"): the
// volume's emission and absorption integrated down the ellipsoid's normal in horizontal slabs
// (volume_march.frag with MARCH_COLUMNS), laid along each pixel's ray. In each slab the ray's
// piece takes the slab's texel at the piece's middle, its optical depth scaled by the piece's
// length over the slab's thickness (the slab taken as uniform along the piece); seen slantwise
// (FAR_FIELD_MAX_SUBPIECES > 1) a piece is cut into sub-pieces that each run at most a pixel
// sideways, each taking its own texel. Pieces are composited front to back and end at the globe's
// depth.
in vec2 v_uv;

uniform sampler2DArray u_slabs;  // RGBA16F premultiplied, linear: layer k = slab k, from the top down
uniform sampler2D u_globeDepth;  // reverse-Z depth of the globe pass
uniform mat3 u_cameraToEcef;
uniform float u_focalPx;
uniform vec2 u_imageSizePx;
uniform float u_near;
uniform vec3 u_eyeEcef;  // float (metres off): the far field serves pixels kilometres wide
uniform vec4 u_box;      // the slabs' texels: lonWestDeg, latSouthDeg, lonStepDeg, latStepDeg
uniform vec2 u_texels;   // columns, rows
uniform int u_slabCount;
uniform float u_heights[FAR_FIELD_MAX_SLABS + 1];  // the slabs' boundaries (m above the ellipsoid), from the top down
// The levels of merged slabs (FarFieldGL::levelsOf): level 0 the slabs above, each level above it
// their pairs merged; per level its first slab in the slab arrays, its count and its thickest.
uniform int u_levelCount;
uniform int u_levelFirst[FAR_FIELD_MAX_LEVELS];
uniform int u_levelSlabs[FAR_FIELD_MAX_LEVELS];
uniform float u_levelThickest[FAR_FIELD_MAX_LEVELS];
uniform int u_slabLayer[FAR_FIELD_MAX_LEVEL_SLABS];     // the slab's layer of u_slabs
uniform float u_slabTop[FAR_FIELD_MAX_LEVEL_SLABS];     // its boundaries (m above the ellipsoid)
uniform float u_slabBottom[FAR_FIELD_MAX_LEVEL_SLABS];
// The mask (FarFieldGL::makeMask): R8, 1 where a column holds anything, its levels regions of one
// texture (x, y, width, height: FarFieldGL::maskAtlas). Not GL mip levels: pixels side by side
// ask for different levels, and llvmpipe's textureSize(sampler, level) is wrong where the level
// varies from pixel to pixel (it skipped storms' pixels: FarFieldMask.PixelsAskingFor...).
uniform sampler2D u_mask;
uniform int u_hasMask;  // 0: no mask, every pixel visits the slabs
uniform int u_maskLevels;
uniform ivec4 u_maskLevel[FAR_FIELD_MAX_MASK_LEVELS];

layout(location = 0) out vec4 o_color;

// The ray's interval inside the ellipsoid raised by h (semi-axes a + h, a + h, b + h, within
// metres of the surface at height h for h of tens of km), from the perpendicular part of the offset
// (float: the Earth's centre is thousands of km away). Empty: x > y.
vec2 shellInterval(vec3 o, vec3 d, float h) {
  float a = WGS84_A + h;
  vec3 s = vec3(1.0, 1.0, a / (WGS84_A * (1.0 - WGS84_F) + h));
  vec3 os = o * s, ds = d * s;
  float len = length(ds);
  vec3 u = ds / len;
  float b = dot(os, u);
  float perp = length(os - b * u);
  if (perp > a) return vec2(1.0, 0.0);
  float sq = sqrt((a - perp) * (a + perp));
  return vec2((-b - sq) / len, (-b + sq) / len);
}

// Texel coordinates (columns, rows from the box's corner, longitude unwrapped: x may run past the
// grid's width or below 0 where the box spans the antimeridian's side) and geodetic latitude of
// the ellipsoid's point below p (within 100 m at 20 km).
vec3 texelAt(vec3 p) {
  float lon = degrees(atan(p.y, p.x));
  float lat = degrees(atan(p.z, (1.0 - WGS84_E2) * length(p.xy)));
  return vec3(mod(lon - u_box.x, 360.0) / u_box.z, (lat - u_box.y) / u_box.w, lat);
}

// The ray's texel coordinates: exact at its ends in the slabs (g_tA, g_tB), interpolated in t
// between them where the chord is under 50 km and below 75 deg of latitude (g_linear); each
// piece's exact otherwise. There the interpolated point is within 240 m of the exact one (computed
// for chords of 50 km at every heading, 0-75 deg, from 0-40 km up: 140 m at 60 deg, 240 m at 75;
// docs/networks.md); pixels here are 2 km or wider.
bool g_linear = false;
float g_tA = 0.0, g_tB = 1.0;
vec2 g_uvA = vec2(0.0), g_uvB = vec2(0.0);

// Whether the mask holds nothing over texel coordinates lo..hi (widened by a texel: a bilinear
// lookup at uv reads texels floor(uv - 0.5) and the next): at the smallest level whose texels are
// as wide as that span, which it crosses in at most two texels a side (FarFieldGL::makeMask: level
// 0's texel x is in texel min(x >> l, size - 1) of level l). False where a longitude wrap could
// bring a piece into the box from the other side.
bool emptyAlong(vec2 lo, vec2 hi) {
  float wrap = 360.0 / u_box.z;
  if ((lo.x < 0.0 && lo.x + wrap <= u_texels.x + 1.0) || hi.x >= wrap) return false;
  ivec2 size0 = ivec2(u_texels);
  ivec2 i0 = clamp(ivec2(floor(lo)) - 1, ivec2(0), size0 - 1);
  ivec2 i1 = clamp(ivec2(floor(hi)) + 1, ivec2(0), size0 - 1);
  if (lo.x > u_texels.x + 1.0 || lo.y > u_texels.y + 1.0 || hi.x < -1.0 || hi.y < -1.0) return true;  // outside the box
  int span = max(i1.x - i0.x, i1.y - i0.y) + 1;
  int level = min(findMSB(span) + ((span & (span - 1)) != 0 ? 1 : 0), u_maskLevels - 1);
  ivec4 region = u_maskLevel[level];
  ivec2 c0 = region.xy + min(i0 >> level, region.zw - 1), c1 = region.xy + min(i1 >> level, region.zw - 1);
  float m = texelFetch(u_mask, c0, 0).r + texelFetch(u_mask, ivec2(c1.x, c0.y), 0).r +
            texelFetch(u_mask, ivec2(c0.x, c1.y), 0).r + texelFetch(u_mask, c1, 0).r;
  return m <= 0.0;
}

// The ray's texel coordinates at t (see g_linear), x brought into the grid's width where a
// longitude wrap puts it outside.
vec2 uvAt(float t, vec3 dir) {
  vec2 uv = g_linear ? mix(g_uvA, g_uvB, clamp((t - g_tA) / (g_tB - g_tA), 0.0, 1.0)) : texelAt(u_eyeEcef + t * dir).xy;
  float wrap = 360.0 / u_box.z;
  uv.x = uv.x < 0.0 ? uv.x + wrap : (uv.x >= wrap ? uv.x - wrap : uv.x);
  return uv;
}

// Sub-pieces a metre of the ray needs (see piece()): the sine of its angle from the vertical
// where that is largest (its lowest point in the slabs) over the pixel's width where that is
// smallest (where it enters them).
float g_subPiecesPerMeter = 0.0;

// The slab texture's layer's texel at the ray's point at t, its optical depth scaled by `ratio` (a
// length of ray over the slab's thickness: the slab taken as uniform along it), composited into
// acc.
void subPiece(int layer, float t, float ratio, vec3 dir, inout vec4 acc) {
  vec2 uv = uvAt(t, dir);
  if (uv.x < 0.0 || uv.x > u_texels.x || uv.y < 0.0 || uv.y > u_texels.y) return;
  vec4 c = textureLod(u_slabs, vec3(uv / u_texels, float(layer)), 0.0);
  if (c.a <= 0.0 && all(lessThanEqual(c.rgb, vec3(0.0)))) return;
  float alpha = min(c.a, 0.99999);
  float tau = -log(1.0 - alpha) * ratio;
  float scaled = 1.0 - exp(-tau);
  vec4 s = alpha > 1e-6 ? c * (scaled / alpha) : c * ratio;
  acc.rgb += (1.0 - acc.a) * s.rgb;
  acc.a += (1.0 - acc.a) * s.a;
}

// A slab's piece [t0, t1] of the ray (the slab `thickness` m thick, in `layer`), composited into
// acc: seen slantwise, in sub-pieces that each run at most a pixel's width sideways, each taking
// the texel at its middle, so that a ray near the limb (where a piece of a 2 km slab runs tens of
// km sideways) reads the columns it passes over, not one column far from most of it.
void piece(int layer, float thickness, float t0, float t1, vec3 dir, inout vec4 acc) {
  if (t1 <= t0) return;
#if FAR_FIELD_MAX_SUBPIECES > 1
  int n = int(clamp(ceil((t1 - t0) * g_subPiecesPerMeter), 1.0, float(FAR_FIELD_MAX_SUBPIECES)));
  float dt = (t1 - t0) / float(n);
  float ratio = dt / thickness;
  for (int i = 0; i < n; ++i) subPiece(layer, t0 + (float(i) + 0.5) * dt, ratio, dir, acc);
#else
  // No piece of the view runs a pixel sideways (FarFieldPlan::View::subPieces): one texel.
  subPiece(layer, 0.5 * (t0 + t1), (t1 - t0) / thickness, dir, acc);
#endif
}

void main() {
  vec2 pixel = vec2(v_uv.x * u_imageSizePx.x, (1.0 - v_uv.y) * u_imageSizePx.y);  // from the top
  vec3 dirEye = vec3((pixel.x - 0.5 * u_imageSizePx.x) / u_focalPx, (0.5 * u_imageSizePx.y - pixel.y) / u_focalPx, -1.0);
  vec3 dir = normalize(u_cameraToEcef * dirEye);
  float depth = textureLod(u_globeDepth, v_uv, 0.0).r;
  float tGround = depth > 0.0 ? (u_near / depth) / (-dirEye.z / length(dirEye)) : 1e30;
  vec4 acc = vec4(0.0);
  vec2 top = shellInterval(u_eyeEcef, dir, u_heights[0]);
  if (top.x > top.y) {
    o_color = acc;
    return;
  }
  // The lowest boundary is the ground (the volume's columns end there): a ray that meets it ends.
  vec2 bottom = shellInterval(u_eyeEcef, dir, u_heights[u_slabCount]);
  bool ground = bottom.x <= bottom.y;
  float tEnd = min(tGround, ground ? bottom.x : 1e30);
  g_tA = max(top.x, 0.0);
  g_tB = max(min(tEnd, top.y), g_tA);
  vec3 a = texelAt(u_eyeEcef + g_tA * dir), b = texelAt(u_eyeEcef + g_tB * dir);
  // The longitude unwrapped from a to b (the shorter way round).
  float dLon = (b.x - a.x) * u_box.z;
  dLon -= 360.0 * round(dLon / 360.0);
  g_uvA = a.xy;
  g_uvB = vec2(a.x + dLon / u_box.z, b.y);
  g_linear = g_tB - g_tA < 5.0e4 && g_tB > g_tA && max(abs(a.z), abs(b.z)) < 75.0;
  // Only empty columns along the chord (every piece's bilinear texels within a texel of it): none.
  if (g_linear && u_hasMask != 0 && emptyAlong(min(g_uvA, g_uvB), max(g_uvA, g_uvB))) {
    o_color = acc;
    return;
  }
  // The ray's angle z from the vertical where it is largest in the slabs (its lowest point there:
  // where it ends, or its perigee if it passes above the ground), and the pixel's width w where it
  // is smallest (where the ray enters them).
  vec3 lowest = u_eyeEcef + clamp(-dot(u_eyeEcef, dir), g_tA, g_tB) * dir;
  float cosZ = abs(dot(dir, normalize(lowest)));
  float sinZ = max(sqrt(max(0.0, 1.0 - cosZ * cosZ)), 1e-6);
  float w = max(g_tA / u_focalPx, 1.0);
  // The thickest level whose slabs span at most a quarter of a pixel across the ray (a slab
  // spreads what it holds over its thickness: T sin z <= w / 4; at half a pixel the far field seen
  // 55 deg from the vertical went from 0.18 to 0.23 of 255 from the march, FarFieldTest) and,
  // without sub-pieces, whose pieces run at most a pixel sideways (T tan z <= w). Level 0 is the
  // plan's (FarFieldGL::planFor).
#if FAR_FIELD_MAX_SUBPIECES > 1
  g_subPiecesPerMeter = sinZ / w;
  float allowed = 0.25 * w / sinZ;
#else
  float allowed = w * min(0.25, cosZ) / sinZ;
#endif
  int level = 0;
  for (int l = 1; l < FAR_FIELD_MAX_LEVELS; ++l)
    if (l < u_levelCount && u_levelThickest[l] <= allowed) level = l;
  int first = u_levelFirst[level], count = u_levelSlabs[level];
  // The ray's interval in each boundary's raised ellipsoid: boundary e is slab e's top, boundary
  // count the last slab's bottom.
  vec2 shells[FAR_FIELD_MAX_SLABS + 1];
  for (int e = 0; e <= FAR_FIELD_MAX_SLABS; ++e) {
    if (e > count) break;
    shells[e] = shellInterval(u_eyeEcef, dir, e < count ? u_slabTop[first + e] : u_slabBottom[first + count - 1]);
  }
  // Going down: slab e from where the ray enters its upper boundary to where it enters the lower
  // one (or leaves the upper one, if it passes above the lower boundary) ...
  for (int e = 0; e < FAR_FIELD_MAX_SLABS; ++e) {
    if (e >= count) break;
    bool down = shells[e + 1].x <= shells[e + 1].y;
    piece(u_slabLayer[first + e], u_slabTop[first + e] - u_slabBottom[first + e], max(shells[e].x, 0.0),
          min(down ? shells[e + 1].x : shells[e].y, tEnd), dir, acc);
  }
  // ... and, above the ground, coming back up where it went below a boundary and out again.
  if (!ground) {
    for (int e = FAR_FIELD_MAX_SLABS - 1; e >= 0; --e) {
      if (e >= count) continue;
      if (shells[e + 1].x <= shells[e + 1].y)
        piece(u_slabLayer[first + e], u_slabTop[first + e] - u_slabBottom[first + e], max(shells[e + 1].y, 0.0),
              min(shells[e].y, tEnd), dir, acc);
    }
  }
  o_color = acc;
}
