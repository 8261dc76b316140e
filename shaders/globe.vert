// Globe tile: float32 positions relative to the tile's double-precision centre.
// u_mvp already holds projection * rotation * (centre - eye), computed in double on the CPU.
layout(location = 0) in vec3 a_positionRelCenter;
layout(location = 1) in vec2 a_texCoord;

uniform mat4 u_mvp;
uniform vec4 u_uvTransform;  // (scale.u, scale.v, offset.u, offset.v) into the imagery tile

out vec2 v_uv;

void main() {
  gl_Position = u_mvp * vec4(a_positionRelCenter, 1.0);
  v_uv = a_texCoord * u_uvTransform.xy + u_uvTransform.zw;
}
