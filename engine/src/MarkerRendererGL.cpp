#include <atmoglobe/engine/MarkerRendererGL.h>

#include <glm/gtc/type_ptr.hpp>

namespace atmoglobe::engine {

namespace {
struct MarkerVertex {
  glm::vec3 positionRelEye;
  glm::vec4 color;
  float sizePx;
};
}  // namespace

Result<std::unique_ptr<MarkerRendererGL>> MarkerRendererGL::create(MarkerStyle style) {
  std::vector<std::string> defines;
  if (style == MarkerStyle::Disc) defines.push_back("MARKER_RIM");
  auto program = ShaderProgramGL::create("marker.vert", "marker.frag", defines);
  if (!program) return makeError(program.error());
  std::unique_ptr<MarkerRendererGL> r(new MarkerRendererGL());
  r->style_ = style;
  r->program_ = std::move(*program);
  glCreateVertexArrays(1, &r->vao_);
  glCreateBuffers(1, &r->vbo_);
  glVertexArrayVertexBuffer(r->vao_, 0, r->vbo_, 0, sizeof(MarkerVertex));
  glEnableVertexArrayAttrib(r->vao_, 0);
  glVertexArrayAttribFormat(r->vao_, 0, 3, GL_FLOAT, GL_FALSE, offsetof(MarkerVertex, positionRelEye));
  glVertexArrayAttribBinding(r->vao_, 0, 0);
  glEnableVertexArrayAttrib(r->vao_, 1);
  glVertexArrayAttribFormat(r->vao_, 1, 4, GL_FLOAT, GL_FALSE, offsetof(MarkerVertex, color));
  glVertexArrayAttribBinding(r->vao_, 1, 0);
  glEnableVertexArrayAttrib(r->vao_, 2);
  glVertexArrayAttribFormat(r->vao_, 2, 1, GL_FLOAT, GL_FALSE, offsetof(MarkerVertex, sizePx));
  glVertexArrayAttribBinding(r->vao_, 2, 0);
  return r;
}

MarkerRendererGL::~MarkerRendererGL() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (vbo_) glDeleteBuffers(1, &vbo_);
}

void MarkerRendererGL::draw(const Camera& camera, const std::vector<Marker>& markers, float depthLift) {
  if (markers.empty()) return;
  std::vector<MarkerVertex> vertices;
  vertices.reserve(markers.size());
  for (const Marker& m : markers) {
    const glm::dvec3 ecef = globe::geodeticToEcef({m.latDeg, m.lonDeg, m.heightMeters});
    // The eye is subtracted in double; only the (small) difference is narrowed to float.
    vertices.push_back({glm::vec3(ecef - camera.eyeEcef()), glm::vec4(m.color, 1.0f), m.sizePx});
  }
  glNamedBufferData(vbo_, static_cast<GLsizeiptr>(vertices.size() * sizeof(MarkerVertex)), vertices.data(),
                    GL_STREAM_DRAW);
  program_.use();
  const glm::mat4 viewProjection = glm::mat4(camera.projection() * camera.viewRotation());
  glUniformMatrix4fv(program_.uniform("u_viewProjection"), 1, GL_FALSE, glm::value_ptr(viewProjection));
  glUniform1f(program_.uniform("u_depthLift"), depthLift);
  glEnable(GL_PROGRAM_POINT_SIZE);
  const bool blend = style_ == MarkerStyle::Gaussian;
  if (blend) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
  }
  glBindVertexArray(vao_);
  glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(vertices.size()));
  glBindVertexArray(0);
  if (blend) {
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
  }
}

}  // namespace atmoglobe::engine
