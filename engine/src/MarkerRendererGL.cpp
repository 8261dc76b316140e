#include <atmoglobe/engine/MarkerRendererGL.h>

#include <glm/gtc/type_ptr.hpp>

#include "LoaderGL.h"
#include "VertexLayoutGL.h"

#include <atmoglobe/engine/LabelPlacement.h>
#include <atmoglobe/engine/TextRaster.h>
#include <atmoglobe/globe/Horizon.h>

#include <iostream>

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
  glVertexArrayVertexBuffer(r->labelVao_, 0, r->labelVbo_, 0, sizeof(float) * 5);
  floatAttributeGL(r->labelVao_, 0, 3, 0);
  floatAttributeGL(r->labelVao_, 1, 2, sizeof(float) * 3);
  return r;
}

MarkerRendererGL::~MarkerRendererGL() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (vbo_) glDeleteBuffers(1, &vbo_);
  if (labelVao_) glDeleteVertexArrays(1, &labelVao_);
  if (labelVbo_) glDeleteBuffers(1, &labelVbo_);
  for (auto& [text, t] : labelTextures_) glDeleteTextures(1, &t.texture);
}

const MarkerRendererGL::LabelTexture* MarkerRendererGL::labelTexture(const std::string& text) {
  if (auto it = labelTextures_.find(text); it != labelTextures_.end()) return &it->second;
  const auto& font = Font::dejaVuSans();
  if (!font) {
    if (!fontWarned_) std::cerr << "warning: marker labels not drawn: " << font.error() << "\n";
    fontWarned_ = true;
    return nullptr;
  }
  // Margin: the halo's radius plus one pixel of anti-aliasing around it.
  const int margin = static_cast<int>(std::ceil(kLabelHaloRadiusPx)) + 1;
  const TextMask mask = (*font)->rasterize(text, kLabelPixelHeight, margin);
  if (mask.width <= 0 || mask.height <= 0) return nullptr;
  const std::vector<std::uint8_t> halo = dilateCoverage(mask, kLabelHaloRadiusPx);
  std::vector<std::uint8_t> rg(mask.coverage.size() * 2);
  for (std::size_t i = 0; i < mask.coverage.size(); ++i) rg[2 * i] = mask.coverage[i], rg[2 * i + 1] = halo[i];
  LabelTexture t;
  t.widthPx = mask.width;
  t.heightPx = mask.height;
  glCreateTextures(GL_TEXTURE_2D, 1, &t.texture);
  glTextureStorage2D(t.texture, 1, GL_RG8, mask.width, mask.height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(t.texture, 0, 0, 0, mask.width, mask.height, GL_RG, GL_UNSIGNED_BYTE, rg.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  // Quads are placed on whole pixels with the mask's size: nearest sampling copies it exactly.
  glTextureParameteri(t.texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(t.texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return &labelTextures_.emplace(text, t).first->second;
}

void MarkerRendererGL::drawLabels(const Camera& camera, const std::vector<Marker>& markers, float depthLift) {
  const double w = camera.widthPx(), h = camera.heightPx();
  // Markers in view (in front of the camera, not behind the Earth): each is an obstacle for
  // the labels; those with a label are candidates, bigger markers (radar sites) first.
  std::vector<LabelCandidate> candidates;
  std::vector<const LabelTexture*> textures;
  std::vector<float> depths;
  for (const Marker& m : markers) {
    const glm::dvec3 ecef = globe::geodeticToEcef({m.latDeg, m.lonDeg, m.heightMeters});
    if (globe::isOccludedByEllipsoid(camera.eyeEcef(), ecef)) continue;
    const auto px = camera.projectToPixel(ecef);
    if (!px || px->x < -m.sizePx || px->y < -m.sizePx || px->x > w + m.sizePx || px->y > h + m.sizePx) continue;
    const LabelTexture* t = m.label.empty() ? nullptr : labelTexture(m.label);
    const double along = glm::dot(ecef - camera.eyeEcef(), camera.forwardEcef());
    LabelCandidate c;
    c.anchorXPx = px->x;
    c.anchorYPx = px->y;
    c.markerRadiusPx = 0.5 * m.sizePx;
    c.widthPx = t ? t->widthPx : 0.0;  // no label: an obstacle only
    c.heightPx = t ? t->heightPx : 0.0;
    c.priority = m.sizePx;
    candidates.push_back(c);
    textures.push_back(t);
    depths.push_back(static_cast<float>(camera.nearMeters() / along) * depthLift);
  }
  // The halo margin is inside the box already: no further gap is needed.
  const std::vector<PlacedLabel> placed = placeLabels(candidates, {w, h, 0.0});
  if (placed.empty()) return;
  std::vector<float> vertices;  // x, y, z (NDC), u, v
  for (const PlacedLabel& p : placed) {
    const float x0 = static_cast<float>(std::round(p.box.leftPx)), y0 = static_cast<float>(std::round(p.box.topPx));
    const float x1 = x0 + static_cast<float>(p.box.widthPx), y1 = y0 + static_cast<float>(p.box.heightPx);
    const float depth = depths[p.candidate];
    auto ndcX = [&](float x) { return static_cast<float>(x / w * 2.0 - 1.0); };
    auto ndcY = [&](float y) { return static_cast<float>(1.0 - y / h * 2.0); };
    const float corner[4][4] = {{ndcX(x0), ndcY(y0), 0.0f, 0.0f},
                                {ndcX(x1), ndcY(y0), 1.0f, 0.0f},
                                {ndcX(x1), ndcY(y1), 1.0f, 1.0f},
                                {ndcX(x0), ndcY(y1), 0.0f, 1.0f}};
    for (int idx : {0, 1, 2, 0, 2, 3})
      vertices.insert(vertices.end(), {corner[idx][0], corner[idx][1], depth, corner[idx][2], corner[idx][3]});
  }
  glNamedBufferData(labelVbo_, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)), vertices.data(),
                    GL_STREAM_DRAW);
  labelProgram_.use();
  glUniform1i(labelProgram_.uniform("u_mask"), 0);
  glUniform4f(labelProgram_.uniform("u_textColor"), 1.0f, 1.0f, 1.0f, 1.0f);
  glUniform4f(labelProgram_.uniform("u_haloColor"), 0.0f, 0.0f, 0.0f, 0.85f);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  // No depth test: a label spans ground nearer to the eye than its marker (the globe's depth
  // there would cut it); whether it shows was decided above for the marker (horizon test).
  const GLboolean depthTest = glIsEnabled(GL_DEPTH_TEST);
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glBindVertexArray(labelVao_);
  for (std::size_t i = 0; i < placed.size(); ++i) {
    glBindTextureUnit(0, textures[placed[i].candidate]->texture);
    glDrawArrays(GL_TRIANGLES, static_cast<GLint>(i * 6), 6);
  }
  glBindVertexArray(0);
  glBindTextureUnit(0, 0);
  if (depthTest) glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
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
