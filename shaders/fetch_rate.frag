// What the device can fetch (tools/bench/sample_rate.cpp): each pixel takes u_fetches bilinear
// lookups from a texture shaped like a radar's values (RG16F, one layer per sweep: what each
// sample of sample_polar.glsl reads twice), walking along a row as a ray walks along the gates,
// each pixel from its own place, so neighbouring pixels read neighbouring texels as a march does.
// The sum keeps every fetch alive.
in vec2 v_uv;
uniform sampler2DArray u_values;
uniform int u_fetches;
uniform float u_layers;
layout(location = 0) out vec4 o_color;

void main() {
  vec2 p = v_uv;
  float layer = floor(v_uv.y * u_layers);
  vec2 step = vec2(1.0 / 1024.0, 1.0 / 8192.0);
  vec2 sum = vec2(0.0);
  for (int i = 0; i < u_fetches; ++i) {
    sum += textureLod(u_values, vec3(fract(p), layer), 0.0).rg;
    p += step;
  }
  o_color = vec4(sum, 0.0, 1.0);
}
