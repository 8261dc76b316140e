// Map lines (MapRendererGL): one instance per segment, four vertices (gl_VertexID 0..3, a
// triangle strip) expanded in screen space to the line's width. Each end point arrives as two
// float triples (hi, lo) whose sum is its offset (m) from the chunk's double origin; the eye's
// offset is split the same way, so (hi - eyeHi) + (lo - eyeLo) is the point relative to the eye
// to sub-millimetre precision at any distance. u_viewProjection is projection * view rotation.
// Injected: WGS84_A.
layout(location = 0) in vec3 a_hi0;
layout(location = 1) in vec3 a_lo0;
layout(location = 2) in vec3 a_hi1;
layout(location = 3) in vec3 a_lo1;

uniform vec3 u_eyeHi;
uniform vec3 u_eyeLo;
uniform mat4 u_viewProjection;
uniform vec3 u_originScaled;  // chunk origin / (a, a, b)
uniform vec3 u_invRadii;      // (1/a, 1/a, 1/b)
uniform vec2 u_viewportPx;
uniform float u_halfWidthPx;
uniform float u_depthLift;  // relative: ndc depth (near / distance) multiplied by 1 + this

noperspective out float v_acrossPx;  // signed distance from the centre line (px)
out float v_horizon;                 // > 0 where the point faces the eye (scaled space)

void endPoint(vec3 hi, vec3 lo, out vec4 clip, out float horizon) {
  precise vec3 rel = (hi - u_eyeHi) + (lo - u_eyeLo);  // point - eye (m)
  clip = u_viewProjection * vec4(rel, 1.0);
  // Scaled space: the point P on the unit sphere faces the eye V iff (V - P) . P > 0.
  vec3 p = u_originScaled + (hi + lo) * u_invRadii;
  horizon = dot(-rel * u_invRadii, p) * WGS84_A;  // in metres-ish, away from float underflow
}

void main() {
  vec4 c0, c1;
  float h0, h1;
  endPoint(a_hi0, a_lo0, c0, h0);
  endPoint(a_hi1, a_lo1, c1, h1);
  // Clip the segment to the near plane (reverse-Z: z = near, visible where w >= z).
  float nearW = c0.z * 1.0001;
  float d0 = c0.w - nearW, d1 = c1.w - nearW;
  if (d0 < 0.0 && d1 < 0.0) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // wholly behind: outside the clip volume
    v_acrossPx = 0.0;
    v_horizon = -1.0;
    return;
  }
  if (d0 < 0.0) {
    float t = d0 / (d0 - d1);
    c0 = mix(c0, c1, t);
    h0 = mix(h0, h1, t);
  } else if (d1 < 0.0) {
    float t = d1 / (d1 - d0);
    c1 = mix(c1, c0, t);
    h1 = mix(h1, h0, t);
  }
  vec2 s0 = c0.xy / c0.w * 0.5 * u_viewportPx, s1 = c1.xy / c1.w * 0.5 * u_viewportPx;
  vec2 dir = s1 - s0;
  float len = length(dir);
  dir = len > 1e-6 ? dir / len : vec2(1.0, 0.0);
  vec2 normal = vec2(-dir.y, dir.x);
  int end = gl_VertexID >> 1;                     // 0: first point, 1: second
  float side = (gl_VertexID & 1) == 0 ? -1.0 : 1.0;
  float extent = u_halfWidthPx + 1.0;             // one more pixel for the antialiased edge
  vec4 c = end == 0 ? c0 : c1;
  vec2 offsetPx = side * extent * normal + (end == 0 ? -1.0 : 1.0) * extent * dir;  // square caps join segments
  c.xy += offsetPx / (0.5 * u_viewportPx) * c.w;
  c.z = min(c.z * (1.0 + u_depthLift), c.w);
  gl_Position = c;
  v_acrossPx = side * extent;
  v_horizon = end == 0 ? h0 : h1;
}
