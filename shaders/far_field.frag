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
uniform sampler2D u_mask;  // R8 with levels: 1 where a column holds anything (FarFieldGL::makeMask)
uniform int u_hasMask;     // 0: no mask, every pixel visits the slabs

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
  int level = min(findMSB(span) + ((span & (span - 1)) != 0 ? 1 : 0), textureQueryLevels(u_mask) - 1);
  ivec2 size = textureSize(u_mask, level);
  ivec2 c0 = min(i0 >> level, size - 1), c1 = min(i1 >> level, size - 1);
  float m = texelFetch(u_mask, c0, level).r + texelFetch(u_mask, ivec2(c1.x, c0.y), level).r +
            texelFetch(u_mask, ivec2(c0.x, c1.y), level).r + texelFetch(u_mask, c1, level).r;
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

// Slab k's piece [t0, t1] of the ray, composited into acc: in sub-pieces that each run at most a
// pixel's width sideways, each taking the texel at its middle, so that a ray seen slantwise (near
// the limb a piece of a 2 km slab runs tens of km sideways) reads the columns it passes over, not
// one column far from most of it. Seen within about 50 deg of the vertical a piece is one
// sub-piece.
// Slab k's texel at the ray's point at t, its optical depth scaled by `ratio` (a length of ray
// over the slab's thickness: the slab taken as uniform along it), composited into acc.
void subPiece(int k, float t, float ratio, vec3 dir, inout vec4 acc) {
  vec2 uv = uvAt(t, dir);
  if (uv.x < 0.0 || uv.x > u_texels.x || uv.y < 0.0 || uv.y > u_texels.y) return;
  vec4 c = textureLod(u_slabs, vec3(uv / u_texels, float(k)), 0.0);
  if (c.a <= 0.0 && all(lessThanEqual(c.rgb, vec3(0.0)))) return;
  float alpha = min(c.a, 0.99999);
  float tau = -log(1.0 - alpha) * ratio;
  float scaled = 1.0 - exp(-tau);
  vec4 s = alpha > 1e-6 ? c * (scaled / alpha) : c * ratio;
  acc.rgb += (1.0 - acc.a) * s.rgb;
  acc.a += (1.0 - acc.a) * s.a;
}

void piece(int k, float t0, float t1, vec3 dir, inout vec4 acc) {
  if (t1 <= t0) return;
#if FAR_FIELD_MAX_SUBPIECES > 1
  int n = int(clamp(ceil((t1 - t0) * g_subPiecesPerMeter), 1.0, float(FAR_FIELD_MAX_SUBPIECES)));
  float dt = (t1 - t0) / float(n);
  float ratio = dt / (u_heights[k] - u_heights[k + 1]);
  for (int i = 0; i < n; ++i) subPiece(k, t0 + (float(i) + 0.5) * dt, ratio, dir, acc);
#else
  // No piece of the view runs a pixel sideways (FarFieldPlan::View::subPieces): one texel.
  subPiece(k, 0.5 * (t0 + t1), (t1 - t0) / (u_heights[k] - u_heights[k + 1]), dir, acc);
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
  // The lowest point of the ray in the slabs: where it ends, or its perigee if it passes above the
  // ground.
#if FAR_FIELD_MAX_SUBPIECES > 1
  vec3 lowest = u_eyeEcef + clamp(-dot(u_eyeEcef, dir), g_tA, g_tB) * dir;
  float cosZ = dot(dir, normalize(lowest));
  g_subPiecesPerMeter = sqrt(max(0.0, 1.0 - cosZ * cosZ)) / max(g_tA / u_focalPx, 1.0);
#endif
  // Only empty columns along the chord (every piece's bilinear texels within a texel of it): none.
  if (g_linear && u_hasMask != 0 && emptyAlong(min(g_uvA, g_uvB), max(g_uvA, g_uvB))) {
    o_color = acc;
    return;
  }
  vec2 shells[FAR_FIELD_MAX_SLABS + 1];
  for (int j = 0; j <= FAR_FIELD_MAX_SLABS; ++j)
    shells[j] = j <= u_slabCount ? shellInterval(u_eyeEcef, dir, u_heights[j]) : vec2(1.0, 0.0);
  // Going down: slab k from where the ray enters its upper boundary to where it enters the
  // lower one (or leaves the upper one, if it passes above the lower boundary) ...
  for (int k = 0; k < FAR_FIELD_MAX_SLABS; ++k) {
    if (k >= u_slabCount) break;
    bool down = shells[k + 1].x <= shells[k + 1].y;
    piece(k, max(shells[k].x, 0.0), min(down ? shells[k + 1].x : shells[k].y, tEnd), dir, acc);
  }
  // ... and, above the ground, coming back up where it went below a boundary and out again.
  if (!ground) {
    for (int k = FAR_FIELD_MAX_SLABS - 1; k >= 0; --k) {
      if (k >= u_slabCount) continue;
      if (shells[k + 1].x <= shells[k + 1].y) piece(k, max(shells[k + 1].y, 0.0), min(shells[k].y, tEnd), dir, acc);
    }
  }
  o_color = acc;
}
