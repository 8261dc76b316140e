// A 2-D field draped on the globe (SurfaceFieldGL): one vertex per grid point on the WGS84
// ellipsoid, as a float (hi, lo) pair relative to the field's double origin (the eye's offset
// split alike: the point relative to the eye to sub-millimetre precision, as map lines), with its
// grid coordinates (column i, row j). The fragment interpolates the values bilinearly at the
// interpolated (i, j), as the CPU sampler does. The depth is lifted toward the eye as map lines
// are (the chords of the field and of the globe's tiles sag differently), and the far side of the
// Earth is cut analytically. Injected: WGS84_A.
layout(location = 0) in vec3 a_hi;
layout(location = 1) in vec3 a_lo;
layout(location = 2) in vec2 a_ij;

uniform vec3 u_eyeHi;
uniform vec3 u_eyeLo;
uniform mat4 u_viewProjection;
uniform vec3 u_originScaled;  // origin / (a, a, b)
uniform vec3 u_invRadii;      // (1/a, 1/a, 1/b)
uniform float u_depthLift;

out vec2 v_ij;
out float v_horizon;  // > 0 where the point faces the eye (scaled space)

void main() {
  precise vec3 rel = (a_hi - u_eyeHi) + (a_lo - u_eyeLo);
  vec4 c = u_viewProjection * vec4(rel, 1.0);
  vec3 p = u_originScaled + (a_hi + a_lo) * u_invRadii;
  v_horizon = dot(-rel * u_invRadii, p) * WGS84_A;
  c.z = min(c.z * (1.0 + u_depthLift), c.w);
  gl_Position = c;
  v_ij = a_ij;
}
