// Marker labels: screen-space quads placed in NDC on the CPU (LabelPlacement.h), textured with
// the label's TrueType coverage and halo (TextRaster.h), at the marker's own reverse-Z depth so
// the globe hides labels of hidden markers.
layout(location = 0) in vec3 a_ndc;
layout(location = 1) in vec2 a_uv;
out vec2 v_uv;
void main() {
  gl_Position = vec4(a_ndc, 1.0);
  v_uv = a_uv;
}
