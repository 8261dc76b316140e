// Map lines (MapRendererGL): antialiased across the line; the far side of the Earth discarded
// by the analytic horizon test (the globe's depth decides the rest).
noperspective in float v_acrossPx;
in float v_horizon;

uniform vec4 u_color;  // straight alpha
uniform float u_halfWidthPx;

out vec4 fragColor;

void main() {
  if (v_horizon < 0.0) discard;
  float coverage = clamp(u_halfWidthPx + 0.5 - abs(v_acrossPx), 0.0, 1.0);
  if (coverage <= 0.0) discard;
  fragColor = vec4(u_color.rgb, u_color.a * coverage);
}
