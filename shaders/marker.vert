// Markers: one point sprite per marker. Positions arrive relative to the eye (m),
// subtracted in double on the CPU; u_viewProjection is projection * rotation (no
// translation).
layout(location = 0) in vec3 a_positionRelEye;
layout(location = 1) in vec4 a_color;
layout(location = 2) in float a_sizePx;

uniform mat4 u_viewProjection;
uniform float u_depthLift;  // >1 pulls the marker's depth towards the eye (ndc z = near / distance)

out vec4 v_color;

void main() {
  gl_Position = u_viewProjection * vec4(a_positionRelEye, 1.0);
  gl_Position.z *= u_depthLift;
  gl_PointSize = a_sizePx;
  v_color = a_color;
}
