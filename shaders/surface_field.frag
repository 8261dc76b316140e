// A 2-D field draped on the globe (SurfaceFieldGL): the value bilinear in the grid's fractional
// column and row from the four grid points around it (texelFetch, exact floats; column nx wraps
// to 0 on a grid that wraps in longitude), missing when any of the four is; the colour from the
// table texture (its RGB; a value below the table's first stop is not drawn), with the layer's
// opacity.
in vec2 v_ij;
in float v_horizon;

uniform sampler2D u_values;  // R32F, nx x ny; missing: >= 1e37
uniform sampler1D u_table;   // RGBA8 over [u_tableRange.x, u_tableRange.y], linear
uniform vec2 u_tableRange;   // field units at the first and last entry's centre
uniform float u_firstStop;   // field units: below it nothing is drawn
uniform float u_opacity;
uniform int u_wraps;

out vec4 fragColor;

float valueAt(ivec2 ij, ivec2 size) {
  if (u_wraps == 1) ij.x = ij.x % size.x;
  return texelFetch(u_values, clamp(ij, ivec2(0), size - 1), 0).r;
}

void main() {
  if (v_horizon < 0.0) discard;
  ivec2 size = textureSize(u_values, 0);
  vec2 ij = max(v_ij, vec2(0.0));
  ivec2 i0 = ivec2(floor(ij));
  vec2 f = ij - vec2(i0);
  float v00 = valueAt(i0, size), v10 = valueAt(i0 + ivec2(1, 0), size);
  float v01 = valueAt(i0 + ivec2(0, 1), size), v11 = valueAt(i0 + ivec2(1, 1), size);
  // Weights of zero do not need their value (the last row or column of a grid).
  bool missing = (v00 >= 1e37 && (1.0 - f.x) * (1.0 - f.y) > 0.0) || (v10 >= 1e37 && f.x * (1.0 - f.y) > 0.0) ||
                 (v01 >= 1e37 && (1.0 - f.x) * f.y > 0.0) || (v11 >= 1e37 && f.x * f.y > 0.0);
  if (missing) discard;
  float v = mix(mix(v00 < 1e37 ? v00 : 0.0, v10 < 1e37 ? v10 : 0.0, f.x),
                mix(v01 < 1e37 ? v01 : 0.0, v11 < 1e37 ? v11 : 0.0, f.x), f.y);
  if (v < u_firstStop) discard;
  int n = textureSize(u_table, 0);
  float u = ((v - u_tableRange.x) / (u_tableRange.y - u_tableRange.x) * float(n - 1) + 0.5) / float(n);
  vec3 rgb = texture(u_table, clamp(u, 0.5 / float(n), 1.0 - 0.5 / float(n))).rgb;
  fragColor = vec4(rgb, u_opacity);
}
