// Globe tile: unlit imagery (colours stay those of the source image), or a base colour
// while no imagery is resident for the tile or any of its ancestors.
in vec2 v_uv;

uniform sampler2D u_imagery;
uniform bool u_hasImagery;
uniform vec3 u_baseColor;

layout(location = 0) out vec4 o_color;

void main() {
  o_color = u_hasImagery ? vec4(texture(u_imagery, v_uv).rgb, 1.0) : vec4(u_baseColor, 1.0);
}
