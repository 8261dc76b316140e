// A round marker whose coverage falls off as a Gaussian from the exact projected
// centre (gl_PointCoord is measured from it), so its intensity-weighted centroid is the
// sub-pixel position of the marker; a dark rim keeps it readable on any imagery.
in vec4 v_color;

layout(location = 0) out vec4 o_color;

void main() {
  vec2 d = gl_PointCoord * 2.0 - 1.0;  // -1..1 across the sprite
  float r2 = dot(d, d);
  if (r2 > 1.0) discard;
  float w = exp(-r2 * 4.0);           // sigma = sprite radius / (2 sqrt 2)
#ifdef MARKER_RIM
  vec3 rgb = mix(v_color.rgb, vec3(0.0), smoothstep(0.55, 0.9, r2));
  o_color = vec4(rgb, 1.0) * (r2 < 0.9 ? 1.0 : 0.0);
  if (r2 >= 0.9) discard;
#else
  o_color = vec4(v_color.rgb * w, w);  // premultiplied
#endif
}
