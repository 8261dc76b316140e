// The label texture: r = text coverage, g = halo coverage (the text dilated). Text over halo,
// premultiplied alpha (blended with ONE, ONE_MINUS_SRC_ALPHA).
in vec2 v_uv;
uniform sampler2D u_mask;
uniform vec4 u_textColor;
uniform vec4 u_haloColor;
layout(location = 0) out vec4 o_color;
void main() {
  vec2 c = texture(u_mask, v_uv).rg;
  float t = c.r * u_textColor.a;
  float h = c.g * u_haloColor.a * (1.0 - t);
  o_color = vec4(u_textColor.rgb * t + u_haloColor.rgb * h, t + h);
}
