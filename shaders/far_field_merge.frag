// A merged slab of the far field (engine/FarFieldGL.h, FarFieldGL::levelsOf): two slabs of the
// level below, one over the other, composited as the column's march composites its samples
// (front to back from the top): premultiplied colour and opacity of the upper, then the lower
// through what the upper lets pass.
uniform sampler2DArray u_slabs;
uniform int u_upper;  // the upper slab's layer
uniform int u_lower;  // the lower slab's layer

layout(location = 0) out vec4 o_color;

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  vec4 upper = texelFetch(u_slabs, ivec3(texel, u_upper), 0);
  vec4 lower = texelFetch(u_slabs, ivec3(texel, u_lower), 0);
  o_color = upper + (1.0 - upper.a) * lower;
}
