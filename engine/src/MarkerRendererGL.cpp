#include <atmoglobe/engine/MarkerRendererGL.h>

#include <glm/gtc/type_ptr.hpp>

#include "VertexLayoutGL.h"

#include <stb/stb_easy_font.h>

#include <cmath>

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
  if (!program) return program.forwardError();
  std::unique_ptr<MarkerRendererGL> r(new MarkerRendererGL());
  r->style_ = style;
  r->program_ = std::move(*program);
  glCreateVertexArrays(1, &r->vao_);
  glCreateBuffers(1, &r->vbo_);
  glVertexArrayVertexBuffer(r->vao_, 0, r->vbo_, 0, sizeof(MarkerVertex));
  floatAttributeGL(r->vao_, 0, 3, offsetof(MarkerVertex, positionRelEye));
  floatAttributeGL(r->vao_, 1, 4, offsetof(MarkerVertex, color));
  floatAttributeGL(r->vao_, 2, 1, offsetof(MarkerVertex, sizePx));
  auto labels = ShaderProgramGL::create("label.vert", "label.frag");
  if (!labels) return labels.forwardError();
  r->labelProgram_ = std::move(*labels);
  glCreateVertexArrays(1, &r->labelVao_);
  glCreateBuffers(1, &r->labelVbo_);
  glVertexArrayVertexBuffer(r->labelVao_, 0, r->labelVbo_, 0, sizeof(float) * 7);
  floatAttributeGL(r->labelVao_, 0, 3, 0);
  floatAttributeGL(r->labelVao_, 1, 4, sizeof(float) * 3);
  return r;
}

MarkerRendererGL::~MarkerRendererGL() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (vbo_) glDeleteBuffers(1, &vbo_);
  if (labelVao_) glDeleteVertexArrays(1, &labelVao_);
  if (labelVbo_) glDeleteBuffers(1, &labelVbo_);
}

void MarkerRendererGL::drawLabels(const Camera& camera, const std::vector<Marker>& markers, float depthLift) {
  constexpr float kScale = 2.0f;  // stb_easy_font glyphs are ~6x7 px; doubled for legibility
  std::vector<float> vertices;    // x, y, z (NDC), r, g, b, a
  std::vector<char> quads(64 * 1024);
  const double w = camera.widthPx(), h = camera.heightPx();
  for (const Marker& m : markers) {
    if (m.label.empty()) continue;
    const glm::dvec3 ecef = globe::geodeticToEcef({m.latDeg, m.lonDeg, m.heightMeters});
    const auto px = camera.projectToPixel(ecef);
    if (!px) continue;
    const double along = glm::dot(ecef - camera.eyeEcef(), camera.forwardEcef());
    const float depth = static_cast<float>(camera.nearMeters() / along) * depthLift;
    std::string text = m.label;
    const int n = stb_easy_font_print(0.0f, 0.0f, text.data(), nullptr, quads.data(), static_cast<int>(quads.size()));
    const float x0 = static_cast<float>(px->x) + 0.5f * m.sizePx + 4.0f;
    const float y0 = static_cast<float>(px->y) - 7.0f * kScale * 0.5f;
    // A dark shadow offset by one pixel, then the text.
    for (int pass = 0; pass < 2; ++pass) {
      const float off = pass == 0 ? 1.0f : 0.0f;
      const glm::vec4 color = pass == 0 ? glm::vec4(0, 0, 0, 1) : glm::vec4(1, 1, 1, 1);
      for (int q = 0; q < n; ++q) {
        const float* v = reinterpret_cast<const float*>(quads.data() + static_cast<std::size_t>(q) * 64);
        glm::vec2 corner[4];
        for (int c = 0; c < 4; ++c) {
          const float sx = x0 + off + kScale * v[c * 4 + 0], sy = y0 + off + kScale * v[c * 4 + 1];
          corner[c] = glm::vec2(static_cast<float>(sx / w * 2.0 - 1.0), static_cast<float>(1.0 - sy / h * 2.0));
        }
        for (int idx : {0, 1, 2, 0, 2, 3}) {
          vertices.insert(vertices.end(), {corner[idx].x, corner[idx].y, depth, color.r, color.g, color.b, color.a});
        }
      }
    }
  }
  if (vertices.empty()) return;
  glNamedBufferData(labelVbo_, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)), vertices.data(),
                    GL_STREAM_DRAW);
  labelProgram_.use();
  glBindVertexArray(labelVao_);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size() / 7));
  glBindVertexArray(0);
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
  } else {
    drawLabels(camera, markers, depthLift);
  }
}

}  // namespace atmoglobe::engine
