// Slices on the globe (SliceRendererGL.h). Drawn with the textured-model program (globe.vert +
// model.frag: positions relative to an origin, straight-alpha texture, transparent texels
// discarded so they write no depth).
#include <atmoglobe/engine/SliceRendererGL.h>

#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <glm/gtc/type_ptr.hpp>

#include "LoaderGL.h"
#include "VertexLayoutGL.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace atmoglobe::engine {
namespace {

// The slice point at pixel (x, y), drawn at `factor` times its height (vertical exaggeration).
glm::dvec3 drawnEcef(const volume::SliceGeometry& g, double x, double y, double factor) {
  const glm::dvec3 p = g.ecefAt(x, y);
  if (factor == 1.0) return p;
  globe::Geodetic geo = globe::ecefToGeodetic(p);
  geo.heightMeters *= factor;
  return globe::geodeticToEcef(geo);
}

void pushVertex(std::vector<float>& out, const volume::SliceGeometry& g, const glm::dvec3& origin, double x, double y,
                double factor) {
  const glm::vec3 p(drawnEcef(g, x, y, factor) - origin);
  out.insert(out.end(), {p.x, p.y, p.z, static_cast<float>(x / g.columns()), static_cast<float>(y / g.rows())});
}

}  // namespace

SliceMesh buildSliceMesh(const volume::SliceGeometry& g, double maxSegmentMeters, double exaggeration) {
  SliceMesh m;
  const double cols = g.columns(), rows = g.rows();
  m.originEcef = drawnEcef(g, 0.5 * cols, 0.5 * rows, exaggeration);
  // Column and row stops (continuous pixel coordinates) of the vertices.
  std::vector<double> xs, ys;
  if (g.kind() == volume::SliceGeometry::Kind::Cappi) {
    const double midLat = g.yValue(0.5 * rows);
    const double widthMeters = std::abs(g.xLast() - g.xFirst()) * 111320.0 * std::cos(midLat * M_PI / 180.0);
    const double heightMeters = std::abs(g.yTop() - g.yBottom()) * 110574.0;
    const int nu = std::clamp(static_cast<int>(std::ceil(widthMeters / maxSegmentMeters)), 1, 1024);
    const int nv = std::clamp(static_cast<int>(std::ceil(heightMeters / maxSegmentMeters)), 1, 1024);
    for (int a = 0; a <= nu; ++a) xs.push_back(cols * a / nu);
    for (int b = 0; b <= nv; ++b) ys.push_back(rows * b / nv);
  } else {
    const double length = g.path().lengthMeters();
    const int n = std::clamp(static_cast<int>(std::ceil(length / maxSegmentMeters)), 1, 4096);
    for (int a = 0; a <= n; ++a) xs.push_back(cols * a / n);
    for (double d : g.path().pointDistancesMeters()) xs.push_back(cols * d / length);  // bend at the points
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end(), [](double p, double q) { return std::abs(p - q) < 1e-9; }), xs.end());
    ys = {0.0, rows};  // straight up the normal: exact with one segment
  }
  const auto nx = static_cast<std::uint32_t>(xs.size()), ny = static_cast<std::uint32_t>(ys.size());
  for (double y : ys)
    for (double x : xs) pushVertex(m.vertices, g, m.originEcef, x, y, exaggeration);
  for (std::uint32_t b = 0; b + 1 < ny; ++b)
    for (std::uint32_t a = 0; a + 1 < nx; ++a) {
      const std::uint32_t i = b * nx + a;
      m.indices.insert(m.indices.end(), {i, i + 1, i + nx, i + 1, i + nx + 1, i + nx});
    }
  // The outline: top edge, right edge, bottom edge back, left edge up.
  for (double x : xs) pushVertex(m.outline, g, m.originEcef, x, ys.front(), exaggeration);
  for (std::size_t b = 1; b < ys.size(); ++b) pushVertex(m.outline, g, m.originEcef, xs.back(), ys[b], exaggeration);
  for (std::size_t a = xs.size() - 1; a-- > 0;) pushVertex(m.outline, g, m.originEcef, xs[a], ys.back(), exaggeration);
  for (std::size_t b = ys.size() - 1; b-- > 0;) pushVertex(m.outline, g, m.originEcef, xs.front(), ys[b], exaggeration);
  return m;
}

globe::ImageRGBA8 sliceTexture(const volume::SliceRaster& r, const volume::ColorTable& colors, double opacity) {
  globe::ImageRGBA8 img = globe::ImageRGBA8::filled(r.columns, r.rows, {0, 0, 0, 0});
  const auto alpha = static_cast<std::uint8_t>(std::lround(std::clamp(opacity, 0.0, 1.0) * 255.0));
  for (int j = 0; j < r.rows; ++j)
    for (int i = 0; i < r.columns; ++i) {
      glm::u8vec4 c = slicePixelColor(colors, r.at(i, j), {0, 0, 0, 0}, {0, 0, 0, 0});
      if (c.a) c.a = alpha;
      img.set(i, j, c);
    }
  return img;
}

Result<std::unique_ptr<SliceRendererGL>> SliceRendererGL::create() {
  auto program = ShaderProgramGL::create("globe.vert", "model.frag");
  if (!program) return program.forwardError();
  std::unique_ptr<SliceRendererGL> r(new SliceRendererGL());
  r->program_ = std::move(*program);
  return r;
}

SliceRendererGL::~SliceRendererGL() {
  for (SliceGL& s : slices_) {
    for (GLuint* vao : {&s.vao, &s.outlineVao})
      if (*vao) glDeleteVertexArrays(1, vao);
    for (GLuint* buffer : {&s.vbo, &s.ibo, &s.outlineVbo})
      if (*buffer) glDeleteBuffers(1, buffer);
    if (s.texture) glDeleteTextures(1, &s.texture);
  }
}

void SliceRendererGL::add(const volume::SliceGeometry& geometry, const volume::SliceRaster& raster,
                          const volume::ColorTable& colors, double opacity) {
  const SliceMesh mesh = buildSliceMesh(geometry, 5000.0, exaggeration_);
  const globe::ImageRGBA8 texture = sliceTexture(raster, colors, opacity);
  SliceGL s;
  s.originEcef = mesh.originEcef;
  s.indexCount = static_cast<GLsizei>(mesh.indices.size());
  s.outlineCount = static_cast<GLsizei>(mesh.outline.size() / 5);
  glCreateVertexArrays(1, &s.vao);
  glCreateBuffers(1, &s.vbo);
  glCreateBuffers(1, &s.ibo);
  glNamedBufferStorage(s.vbo, static_cast<GLsizeiptr>(mesh.vertices.size() * 4), mesh.vertices.data(), 0);
  glNamedBufferStorage(s.ibo, static_cast<GLsizeiptr>(mesh.indices.size() * 4), mesh.indices.data(), 0);
  glVertexArrayVertexBuffer(s.vao, 0, s.vbo, 0, 5 * sizeof(float));
  glVertexArrayElementBuffer(s.vao, s.ibo);
  floatAttributeGL(s.vao, 0, 3, 0);
  floatAttributeGL(s.vao, 1, 2, 3 * sizeof(float));
  glCreateVertexArrays(1, &s.outlineVao);
  glCreateBuffers(1, &s.outlineVbo);
  glNamedBufferStorage(s.outlineVbo, static_cast<GLsizeiptr>(mesh.outline.size() * 4), mesh.outline.data(), 0);
  glVertexArrayVertexBuffer(s.outlineVao, 0, s.outlineVbo, 0, 5 * sizeof(float));
  floatAttributeGL(s.outlineVao, 0, 3, 0);
  floatAttributeGL(s.outlineVao, 1, 2, 3 * sizeof(float));
  glCreateTextures(GL_TEXTURE_2D, 1, &s.texture);
  glTextureStorage2D(s.texture, 1, GL_RGBA8, texture.width, texture.height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(s.texture, 0, 0, 0, texture.width, texture.height, GL_RGBA, GL_UNSIGNED_BYTE,
                      texture.pixels.data());
  // Nearest: each texel is one sampled value, shown as the plot shows it.
  glTextureParameteri(s.texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(s.texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(s.texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(s.texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  slices_.push_back(s);
}

Result<std::string> SliceRendererGL::add(const SliceLayerDescription& d) {
  auto source = volume::SliceSource::load(d.source);
  if (!source) return source.forwardError();
  auto transfer = (*source)->transfer(d.colors, d.range);
  if (!transfer) return transfer.forwardError();
  volume::SliceRequest request = d.request;
  // The raster: resolutionPx along the longer side, the other side by the slice's shape.
  request.columns = request.rows = 16;
  auto probe = volume::sliceGeometryFor(**source, request);
  if (!probe) return probe.forwardError();
  double aspect = 4.0;  // cross-section: distance x height, 4:1
  if (probe->kind() == volume::SliceGeometry::Kind::Cappi) {
    const double midLat = 0.5 * (probe->yTop() + probe->yBottom());
    aspect = (probe->xLast() - probe->xFirst()) * std::max(0.05, std::cos(midLat * M_PI / 180.0)) /
             (probe->yTop() - probe->yBottom());
  }
  request.columns = aspect >= 1.0 ? d.resolutionPx
                                  : std::max(8, static_cast<int>(std::lround(d.resolutionPx * aspect)));
  request.rows = aspect >= 1.0 ? std::max(8, static_cast<int>(std::lround(d.resolutionPx / aspect))) : d.resolutionPx;
  auto geometry = volume::sliceGeometryFor(**source, request);
  if (!geometry) return geometry.forwardError();
  auto raster = volume::sampleSource(**source, *geometry);
  if (!raster) return raster.forwardError();
  add(*geometry, *raster, transfer->colors, d.opacity);
  const SlicePlotOptions text = slicePlotOptionsFor(**source, *geometry, *transfer, 640, 480);
  char figures[160];
  std::snprintf(figures, sizeof figures, ": %d x %d px, %zu echo pixels", raster->columns, raster->rows,
                raster->echoCount);
  std::string index;  // the netCDF index dimensions read ("month 3 (index 2)"), as in the slice's subtitle
  if (const volume::GridVolume* grid = (*source)->grid())
    if (const std::string indexText = volume::extraIndexText(*grid); !indexText.empty()) index = ", " + indexText;
  return text.title + index + figures;
}

void SliceRendererGL::draw(const Camera& camera) const {
  if (slices_.empty()) return;
  program_.use();
  glUniform1i(program_.uniform("u_imagery"), 0);
  glUniform4f(program_.uniform("u_uvTransform"), 1.0f, 1.0f, 0.0f, 0.0f);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  for (const SliceGL& s : slices_) {
    const glm::mat4 mvp(camera.modelViewProjectionRelativeTo(s.originEcef));
    glUniformMatrix4fv(program_.uniform("u_mvp"), 1, GL_FALSE, glm::value_ptr(mvp));
    glUniform1i(program_.uniform("u_hasImagery"), 1);
    glUniform4f(program_.uniform("u_baseColor"), 1.0f, 1.0f, 1.0f, 1.0f);
    glBindTextureUnit(0, s.texture);
    glBindVertexArray(s.vao);
    glDrawElements(GL_TRIANGLES, s.indexCount, GL_UNSIGNED_INT, nullptr);
    // The outline: light grey, half opaque.
    glUniform1i(program_.uniform("u_hasImagery"), 0);
    glUniform4f(program_.uniform("u_baseColor"), 0.85f, 0.85f, 0.85f, 0.8f);
    glBindVertexArray(s.outlineVao);
    glDrawArrays(GL_LINE_STRIP, 0, s.outlineCount);
  }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
}

}  // namespace atmoglobe::engine
