// Marker labels: screen-space text quads (from stb_easy_font) placed in NDC on the CPU,
// with the marker's own reverse-Z depth so the globe hides labels of hidden markers.
layout(location = 0) in vec3 a_ndc;
layout(location = 1) in vec4 a_color;
out vec4 v_color;
void main() {
  gl_Position = vec4(a_ndc, 1.0);
  v_color = a_color;
}
