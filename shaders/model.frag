// Textured models (e.g. the exported radar cones): straight-alpha texture, premultiplied out;
// fully transparent texels are discarded so they do not write depth.
in vec2 v_uv;
uniform sampler2D u_imagery;
uniform bool u_hasImagery;
uniform vec4 u_baseColor;
layout(location = 0) out vec4 o_color;
void main() {
  vec4 c = u_hasImagery ? texture(u_imagery, v_uv) * u_baseColor : u_baseColor;
  if (c.a < 0.01) discard;
  o_color = vec4(c.rgb * c.a, c.a);
}
