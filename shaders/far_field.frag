// The far field of a volume (engine/FarFieldGL.h; docs/networks.md, "The far field"): the
// volume's emission and absorption integrated down the ellipsoid's normal in horizontal slabs
// (volume_march.frag with MARCH_COLUMNS), laid along each pixel's ray. In each slab the ray's
// piece takes the slab's texel at the piece's middle, its optical depth scaled by the piece's
// length over the slab's thickness (the slab taken as uniform along the piece); pieces are
// composited front to back and end at the globe's depth.
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

// Slab k's piece [t0, t1] of the ray, composited into acc.
void piece(int k, float t0, float t1, vec3 dir, inout vec4 acc) {
  if (t1 <= t0) return;
  vec3 p = u_eyeEcef + 0.5 * (t0 + t1) * dir;
  float lon = degrees(atan(p.y, p.x));
  float lat = degrees(atan(p.z, (1.0 - WGS84_E2) * length(p.xy)));  // geodetic at the surface below p (within 100 m at 20 km)
  float x = mod(lon - u_box.x, 360.0) / u_box.z;
  float y = (lat - u_box.y) / u_box.w;
  if (x < 0.0 || x > u_texels.x || y < 0.0 || y > u_texels.y) return;
  vec4 c = textureLod(u_slabs, vec3(x / u_texels.x, y / u_texels.y, float(k)), 0.0);
  if (c.a <= 0.0 && all(lessThanEqual(c.rgb, vec3(0.0)))) return;
  // Optical depth over the piece: the slab's, times the piece's length over the slab's thickness.
  float ratio = (t1 - t0) / (u_heights[k] - u_heights[k + 1]);
  float alpha = min(c.a, 0.99999);
  float tau = -log(1.0 - alpha) * ratio;
  float scaled = 1.0 - exp(-tau);
  vec4 s = alpha > 1e-6 ? c * (scaled / alpha) : c * ratio;
  acc.rgb += (1.0 - acc.a) * s.rgb;
  acc.a += (1.0 - acc.a) * s.a;
}

void main() {
  vec2 pixel = vec2(v_uv.x * u_imageSizePx.x, (1.0 - v_uv.y) * u_imageSizePx.y);  // from the top
  vec3 dirEye = vec3((pixel.x - 0.5 * u_imageSizePx.x) / u_focalPx, (0.5 * u_imageSizePx.y - pixel.y) / u_focalPx, -1.0);
  vec3 dir = normalize(u_cameraToEcef * dirEye);
  float depth = textureLod(u_globeDepth, v_uv, 0.0).r;
  float tGround = depth > 0.0 ? (u_near / depth) / (-dirEye.z / length(dirEye)) : 1e30;
  vec2 shells[FAR_FIELD_MAX_SLABS + 1];
  for (int j = 0; j <= FAR_FIELD_MAX_SLABS; ++j)
    shells[j] = j <= u_slabCount ? shellInterval(u_eyeEcef, dir, u_heights[j]) : vec2(1.0, 0.0);
  vec4 acc = vec4(0.0);
  if (shells[0].x > shells[0].y) {
    o_color = acc;
    return;
  }
  // The lowest boundary is the ground (the volume's columns end there): a ray that meets it ends.
  bool ground = shells[u_slabCount].x <= shells[u_slabCount].y;
  float tEnd = min(tGround, ground ? shells[u_slabCount].x : 1e30);
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
