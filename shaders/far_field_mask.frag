// The far field's empty-space mask (engine/FarFieldGL.h): 1 where any slab of the texel's column
// holds colour or opacity, else 0; the coarser levels (made on the CPU from this one) let a pixel
// whose ray crosses only empty columns skip its slabs (far_field.frag).
uniform sampler2DArray u_slabs;  // the slabs, from the top down
uniform int u_slabCount;

layout(location = 0) out vec4 o_mask;

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  float found = 0.0;
  for (int k = 0; k < u_slabCount; ++k) {
    vec4 c = texelFetch(u_slabs, ivec3(texel, k), 0);
    if (c.a > 0.0 || any(greaterThan(c.rgb, vec3(0.0)))) found = 1.0;
  }
  o_mask = vec4(found);
}
