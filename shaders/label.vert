// Marker labels: screen-space quads placed in NDC on the CPU (LabelPlacement.h), textured with
// the label's TrueType coverage and halo (TextRaster.h). Drawn without depth test: labels of
// markers behind the Earth are left out on the CPU (MarkerRendererGL).
layout(location = 0) in vec3 a_ndc;
layout(location = 1) in vec2 a_uv;
out vec2 v_uv;
void main() {
  gl_Position = vec4(a_ndc, 1.0);
  v_uv = a_uv;
}
