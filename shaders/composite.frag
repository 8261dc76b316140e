// Lays the (possibly lower-resolution) volume image, premultiplied, over the globe.
in vec2 v_uv;
uniform sampler2D u_volume;
layout(location = 0) out vec4 o_color;
void main() { o_color = texture(u_volume, v_uv); }
