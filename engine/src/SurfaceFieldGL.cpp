// A 2-D field draped on the globe (SurfaceFieldGL.h).
#include <atmoglobe/engine/ShaderConstants.h>
#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/engine/SurfaceFieldGL.h>
#include <atmoglobe/engine/VolumeSourceGL.h>

#include "LoaderGL.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/TransferFunction.h>
#include <atmoglobe/volume/Wind.h>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace atmoglobe::engine {
namespace {
constexpr int kTableEntries = 1024;
constexpr float kMissingTexel = 3.0e38f;  // the shader's "missing": >= 1e37

// x - hi, narrowed; not inlined (GCC 12 SLP bug, as in map/src/GeoLines.cpp).
[[gnu::noinline]] float lowPartOf(double x, float hi) { return static_cast<float>(x - static_cast<double>(hi)); }

/// The longitude and latitude of fractional column i, row j (columns past nx - 1 wrap when the
/// grid does): bilinear between the four grid points around it, longitudes unwrapped against the
/// first of them.
glm::dvec2 lonLatAt(const volume::GridVolume& g, bool wraps, double i, double j) {
  const double columns = static_cast<double>(g.nx + (wraps ? 1 : 0));
  i = std::clamp(i, 0.0, columns - 1.0);
  j = std::clamp(j, 0.0, static_cast<double>(g.ny - 1));
  const std::size_t i0 = std::min(static_cast<std::size_t>(i), static_cast<std::size_t>(columns) - 2);
  const std::size_t j0 = std::min(static_cast<std::size_t>(j), g.ny - 2);
  const double fi = i - static_cast<double>(i0), fj = j - static_cast<double>(j0);
  const double lon00 = g.lonDegAt(j0, i0 % g.nx);
  glm::dvec2 sum(0.0);
  for (int dj = 0; dj < 2; ++dj)
    for (int di = 0; di < 2; ++di) {
      const std::size_t ii = (i0 + static_cast<std::size_t>(di)) % g.nx, jj = j0 + static_cast<std::size_t>(dj);
      double lon = g.lonDegAt(jj, ii);
      lon += 360.0 * std::round((lon00 - lon) / 360.0);
      const double w = (di ? fi : 1.0 - fi) * (dj ? fj : 1.0 - fj);
      sum += w * glm::dvec2(lon, g.latDegAt(jj, ii));
    }
  return sum;
}
/// Where a line's labels go: every kLabelSpacingMeters along it from half that, or its middle when
/// it is shorter (the scene's label placement drops those that would overlap or are not in view).
constexpr double kLabelSpacingMeters = 1.2e6;
std::vector<glm::dvec2> labelPoints(const map::GeoPolyline& line) {
  const std::vector<glm::dvec2>& p = line.lonLatDeg;
  if (p.empty()) return {};
  std::vector<double> along(p.size(), 0.0);  // great-circle distance on the mean sphere (m)
  for (std::size_t k = 1; k < p.size(); ++k) {
    const glm::dvec3 a = globe::geodeticToEcef({p[k - 1].y, p[k - 1].x, 0.0});
    const glm::dvec3 b = globe::geodeticToEcef({p[k].y, p[k].x, 0.0});
    along[k] = along[k - 1] + glm::distance(a, b);
  }
  std::vector<double> at;
  if (along.back() < kLabelSpacingMeters) at.push_back(0.5 * along.back());
  for (double t = 0.5 * kLabelSpacingMeters; t < along.back(); t += kLabelSpacingMeters) at.push_back(t);
  std::vector<glm::dvec2> out;
  std::size_t k = 1;
  for (double t : at) {
    while (k + 1 < p.size() && along[k] < t) ++k;
    if (p.size() == 1) return {p[0]};
    const double span = along[k] - along[k - 1];
    const double f = span > 0.0 ? std::clamp((t - along[k - 1]) / span, 0.0, 1.0) : 0.0;
    out.push_back(p[k - 1] + f * (p[k] - p[k - 1]));
  }
  return out;
}
}  // namespace

Result<std::unique_ptr<SurfaceFieldGL>> SurfaceFieldGL::create(SurfaceData data, const SurfaceLayerDescription& d) {
  volume::SurfaceField& field = data.field;
  const volume::GridVolume& g = field.grid;
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  if (g.nx > static_cast<std::size_t>(maxSize) || g.ny > static_cast<std::size_t>(maxSize))
    return makeError(g.path + ": " + std::to_string(g.nx) + " x " + std::to_string(g.ny) +
                     " grid points: more than this GL's largest texture (" + std::to_string(maxSize) + ")");
  auto program = ShaderProgramGL::create("surface_field.vert", "surface_field.frag", ellipsoidShaderDefines());
  if (!program) return program.forwardError();
  // Colours: the grid's choice for the variable, over the description's range or the values'.
  const volume::ValueRange range{static_cast<double>(g.valueMin), static_cast<double>(g.valueMax)};
  auto transfer = volume::transferForField(d.colors, volume::FieldInfo{g.variable, g.units, g.standardName},
                                           std::numeric_limits<double>::quiet_NaN(), range);
  if (!transfer) return makeError(g.path + ": " + transfer.error());
  volume::TransferFunction tf = std::move(*transfer);
  if (d.valueRange) tf = volume::withValueRange(tf, d.valueRange->x, d.valueRange->y);

  std::unique_ptr<SurfaceFieldGL> s(new SurfaceFieldGL());
  s->program_ = std::move(*program);
  s->description_ = d;
  s->table_ = tf.colors;
  s->field_ = std::move(field);
  s->sampler_ = std::make_unique<volume::SurfaceSampler>(s->field_);
  s->windGrid_ = std::move(data.windGrid);
  s->wind_ = std::move(data.wind);
  s->windNote_ = std::move(data.windNote);
  s->members_ = std::move(data.members);  // moved whole: the samplers below keep references into it
  for (const auto& member : s->members_)
    s->memberSamplers_.push_back(std::make_unique<volume::SurfaceSampler>(member.second));
  const volume::GridVolume& grid = s->field_.grid;
  const bool wraps = grid.wrapsLongitude && !grid.curvilinear;
  const std::size_t nx = grid.nx, ny = grid.ny, columns = nx + (wraps ? 1 : 0);

  // The table over its stops (field units), sampled at kTableEntries points.
  const volume::ColorTable& t = s->table_;
  const double a = (t.stops().front().value - t.offset()) / t.scale(),
               b = (t.stops().back().value - t.offset()) / t.scale();
  s->tableLo_ = std::min(a, b);
  s->tableHi_ = std::max(a, b) > s->tableLo_ ? std::max(a, b) : s->tableLo_ + 1.0;
  std::vector<std::uint8_t> table(4 * kTableEntries);
  for (int k = 0; k < kTableEntries; ++k) {
    const double v = s->tableLo_ + (s->tableHi_ - s->tableLo_) * k / (kTableEntries - 1);
    const volume::Rgba8 c = t.map(static_cast<float>(v));
    table[4 * k + 0] = c.r, table[4 * k + 1] = c.g, table[4 * k + 2] = c.b, table[4 * k + 3] = 255;
  }
  glCreateTextures(GL_TEXTURE_1D, 1, &s->tableTexture_);
  glTextureStorage1D(s->tableTexture_, 1, GL_RGBA8, kTableEntries);
  glTextureSubImage1D(s->tableTexture_, 0, 0, kTableEntries, GL_RGBA, GL_UNSIGNED_BYTE, table.data());
  glTextureParameteri(s->tableTexture_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(s->tableTexture_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(s->tableTexture_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);

  // Values: one texel per grid point.
  std::vector<float> texels(nx * ny);
  for (std::size_t c = 0; c < texels.size(); ++c)
    texels[c] = std::isfinite(grid.values[c]) ? grid.values[c] : kMissingTexel;
  glCreateTextures(GL_TEXTURE_2D, 1, &s->values_);
  glTextureStorage2D(s->values_, 1, GL_R32F, static_cast<GLsizei>(nx), static_cast<GLsizei>(ny));
  glTextureSubImage2D(s->values_, 0, 0, 0, static_cast<GLsizei>(nx), static_cast<GLsizei>(ny), GL_RED, GL_FLOAT,
                      texels.data());

  // The mesh: every grid point (and a wrap column) on the ellipsoid, relative to the grid's middle.
  const glm::dvec2 mid =
      lonLatAt(grid, wraps, 0.5 * static_cast<double>(columns - 1), 0.5 * static_cast<double>(ny - 1));
  s->originEcef_ = globe::geodeticToEcef({std::clamp(mid.y, -90.0, 90.0), mid.x, 0.0});
  std::vector<float> vertices;
  vertices.reserve(columns * ny * 8);
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < columns; ++i) {
      const glm::dvec3 p =
          globe::geodeticToEcef({std::clamp(grid.latDegAt(j, i % nx), -90.0, 90.0), grid.lonDegAt(j, i % nx), 0.0}) -
          s->originEcef_;
      for (int k = 0; k < 3; ++k) vertices.push_back(static_cast<float>(p[k]));
      for (int k = 0; k < 3; ++k) vertices.push_back(lowPartOf(p[k], static_cast<float>(p[k])));
      vertices.push_back(static_cast<float>(i));
      vertices.push_back(static_cast<float>(j));
    }
  std::vector<std::uint32_t> indices;
  const auto missing = [&](std::size_t i, std::size_t j) { return !std::isfinite(grid.values[j * nx + i % nx]); };
  for (std::size_t j = 0; j + 1 < ny; ++j)
    for (std::size_t i = 0; i + 1 < columns; ++i) {
      if (missing(i, j) && missing(i + 1, j) && missing(i, j + 1) && missing(i + 1, j + 1)) continue;
      const auto v = [&](std::size_t ii, std::size_t jj) { return static_cast<std::uint32_t>(jj * columns + ii); };
      indices.insert(indices.end(), {v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  s->indexCount_ = static_cast<int>(indices.size());
  glCreateVertexArrays(1, &s->vao_);
  glCreateBuffers(1, &s->vbo_);
  glNamedBufferStorage(s->vbo_, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)), vertices.data(), 0);
  glCreateBuffers(1, &s->ibo_);
  glNamedBufferStorage(s->ibo_,
                       static_cast<GLsizeiptr>(std::max<std::size_t>(1, indices.size()) * sizeof(std::uint32_t)),
                       indices.empty() ? nullptr : indices.data(), 0);
  glVertexArrayVertexBuffer(s->vao_, 0, s->vbo_, 0, 8 * sizeof(float));
  glVertexArrayElementBuffer(s->vao_, s->ibo_);
  const GLuint sizes[3] = {3, 3, 2};
  for (GLuint k = 0, offset = 0; k < 3; offset += sizes[k], ++k) {
    glEnableVertexArrayAttrib(s->vao_, k);
    glVertexArrayAttribFormat(s->vao_, k, static_cast<GLint>(sizes[k]), GL_FLOAT, GL_FALSE, offset * sizeof(float));
    glVertexArrayAttribBinding(s->vao_, k, 0);
  }
  // Contour lines in the grid's index space (a wrap column closes them across the seam).
  if (d.contourInterval || !d.contourValues.empty()) {
    std::vector<float> raster(columns * ny);
    for (std::size_t j = 0; j < ny; ++j)
      for (std::size_t i = 0; i < columns; ++i) raster[j * columns + i] = grid.values[j * nx + i % nx];
    map::ContourLevels levels;
    levels.interval = d.contourInterval;
    levels.values = d.contourValues;
    auto lines = map::contourLinesOnGrid(raster.data(), static_cast<int>(columns), static_cast<int>(ny), levels,
                                         [&](double i, double j) { return lonLatAt(grid, wraps, i, j); });
    if (!lines) return makeError(grid.path + ": " + lines.error());
    s->contours_ = std::move(*lines);
    auto lineRenderer = MapRendererGL::create("");
    if (!lineRenderer) return lineRenderer.forwardError();
    s->lines_ = std::move(*lineRenderer);
    std::vector<map::GeoPolyline> polylines;
    for (const map::ContourLine& c : s->contours_) {
      polylines.push_back(c.line);
      if (d.contourLabels)
        for (const glm::dvec2& p : labelPoints(c.line)) {
          Marker m;
          m.latDeg = p.y;
          m.lonDeg = p.x;
          m.sizePx = 0.0f;
          m.label = map::contourLabel(c.value);
          s->labels_.push_back(m);
        }
    }
    s->lines_->addLines(polylines, MapLineStyle{d.contourColor, d.contourWidthPx, 1.0f});
  }
  return s;
}

SurfaceFieldGL::~SurfaceFieldGL() {
  glDeleteVertexArrays(1, &vao_);
  glDeleteBuffers(1, &vbo_);
  glDeleteBuffers(1, &ibo_);
  glDeleteTextures(1, &values_);
  glDeleteTextures(1, &tableTexture_);
}

void SurfaceFieldGL::drawFill(const Camera& camera) {
  if (!description_.fill || indexCount_ == 0) return;
  program_.use();
  const glm::mat4 viewProjection(camera.modelViewProjectionRelativeTo(camera.eyeEcef()));
  glUniformMatrix4fv(program_.uniform("u_viewProjection"), 1, GL_FALSE, glm::value_ptr(viewProjection));
  setEyeRelativeUniformsGL(program_, camera.eyeEcef(), originEcef_);
  glUniform1f(program_.uniform("u_depthLift"), kMapDepthLift);
  glUniform2f(program_.uniform("u_tableRange"), static_cast<float>(tableLo_), static_cast<float>(tableHi_));
  glUniform1f(program_.uniform("u_firstStop"), static_cast<float>(tableLo_));
  glUniform1f(program_.uniform("u_opacity"), static_cast<float>(description_.opacity));
  glUniform1i(program_.uniform("u_wraps"), field_.grid.wrapsLongitude && !field_.grid.curvilinear ? 1 : 0);
  glBindTextureUnit(0, values_);
  glBindTextureUnit(1, tableTexture_);
  glUniform1i(program_.uniform("u_values"), 0);
  glUniform1i(program_.uniform("u_table"), 1);
  beginOverGlobeGL();
  glBindVertexArray(vao_);
  glDrawElements(GL_TRIANGLES, indexCount_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
  endOverGlobeGL();
}

void SurfaceFieldGL::drawContours(const Camera& camera) {
  if (lines_) lines_->draw(camera);
  if (!windGrid_) return;
  buildBarbs(camera);
  if (barbs_) barbs_->draw(camera);
}

void SurfaceFieldGL::buildBarbs(const Camera& camera) {
  const volume::GridVolume& g = *windGrid_;
  // The view's scale (metres per pixel at the centre, else at the nearest point of the Earth) and
  // place decide which points carry barbs and how long they are.
  const glm::dvec3 eye = camera.eyeEcef();
  const glm::dvec3 centreDir = camera.pixelRayDirection(0.5 * camera.widthPx(), 0.5 * camera.heightPx());
  const auto centreHit = globe::intersectRayEllipsoid(eye, centreDir);
  const double distance = centreHit ? glm::length(*centreHit - eye)
                                    : std::max(1.0, globe::ecefToGeodetic(eye).heightMeters);
  const double metersPerPx = distance / camera.focalLengthPx();
  // Grid spacing near the grid's middle (m).
  const std::size_t mi = g.nx / 2, mj = g.ny / 2;
  const glm::dvec3 a = globe::geodeticToEcef({g.latDegAt(mj, mi), g.lonDegAt(mj, mi), 0.0});
  const glm::dvec3 b = globe::geodeticToEcef(
      {g.latDegAt(mj, std::min(mi + 1, g.nx - 1)), g.lonDegAt(mj, std::min(mi + 1, g.nx - 1)), 0.0});
  const glm::dvec3 c = globe::geodeticToEcef(
      {g.latDegAt(std::min(mj + 1, g.ny - 1), mi), g.lonDegAt(std::min(mj + 1, g.ny - 1), mi), 0.0});
  const double cellMeters = std::max(1.0, std::min(glm::distance(a, b) > 0.0 ? glm::distance(a, b) : 1e30,
                                                   glm::distance(a, c) > 0.0 ? glm::distance(a, c) : 1e30));
  const std::size_t stride =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(kBarbSpacingPx * metersPerPx / cellMeters)));
  const double lengthMeters = kBarbLengthPx * metersPerPx;
  // Built again when the stride or the barb length changes by a quarter, or the view's centre
  // moves by more than a tenth of the view.
  const glm::dvec3 centre = centreHit ? *centreHit : eye;
  const std::vector<double> key{static_cast<double>(stride), std::round(std::log2(lengthMeters) * 3.0),
                                std::round(centre.x / (metersPerPx * camera.widthPx() * 0.1)),
                                std::round(centre.y / (metersPerPx * camera.widthPx() * 0.1)),
                                std::round(centre.z / (metersPerPx * camera.widthPx() * 0.1))};
  if (key == barbKey_ && barbs_) return;
  barbKey_ = key;
  std::vector<map::GeoPolyline> lines;
  const globe::ViewState view = camera.viewState();
  for (std::size_t j = 0; j < g.ny; j += stride)
    for (std::size_t i = 0; i < g.nx; i += stride) {
      const std::size_t k = j * g.nx + i;
      const double east = wind_.eastMps[k], north = wind_.northMps[k];
      if (!std::isfinite(east) || !std::isfinite(north)) continue;
      const double lat = g.latDegAt(j, i), lon = g.lonDegAt(j, i);
      const glm::dvec3 p = globe::geodeticToEcef({lat, lon, 0.0});
      // In view: in front of the camera, inside the frustum (with a barb's margin) and on the
      // near side of the Earth.
      bool inside = true;
      for (const glm::dvec4& plane : view.frustumPlanesEcef)
        inside = inside && glm::dot(glm::dvec3(plane), p) + plane.w > -lengthMeters;
      const auto axes = globe::enuAxes(lat, lon);
      if (!inside || glm::dot(eye - p, axes[2]) < 0.0) continue;
      for (const std::vector<glm::dvec2>& piece : volume::barbPolylines(east, north, lat < 0.0)) {
        map::GeoPolyline line;
        for (const glm::dvec2& q : piece) {
          const globe::Geodetic gq =
              globe::ecefToGeodetic(p + lengthMeters * (q.x * glm::dvec3(axes[0]) + q.y * glm::dvec3(axes[1])));
          line.lonLatDeg.emplace_back(gq.lonDeg, gq.latDeg);
        }
        lines.push_back(std::move(line));
      }
    }
  if (!barbs_) {
    auto r = MapRendererGL::create("");
    if (!r) return;
    barbs_ = std::move(*r);
  }
  barbs_->clearLines();
  barbs_->addLines(lines, MapLineStyle{description_.windColor, 1.5f, 1.0f});
}

std::string SurfaceFieldGL::title() const { return displayName(field_.name) + " (map)"; }

std::string SurfaceFieldGL::subtitle() const {
  const volume::GridVolume& g = field_.grid;
  std::string s = displayName(field_.name) + " valid " + utcLabel(g.validTime);
  if (windGrid_) s += "  " + windNote_ + ", barbs in knots (pennant 50, barb 10, half 5)";
  if (!volume::memberText(g).empty()) s += "  " + volume::memberText(g);
  if (description_.contourInterval)
    s += "  contours every " + map::contourLabel(*description_.contourInterval) + " " + g.units;
  else if (!description_.contourValues.empty())
    s += "  contours at " + std::to_string(description_.contourValues.size()) + " values";
  return s;
}

std::optional<LegendKey> SurfaceFieldGL::key() const {
  if (!description_.fill) return std::nullopt;
  return LegendKey{displayName(field_.name), field_.grid.units, table_};
}

SurfaceData SurfaceFieldGL::data() const {
  SurfaceData d;
  d.field = field_;
  d.windGrid = windGrid_;
  d.wind = wind_;
  d.windNote = windNote_;
  d.members = members_;
  return d;
}

std::vector<std::pair<long, double>> SurfaceFieldGL::memberValuesAt(double latDeg, double lonDeg) const {
  std::vector<std::pair<long, double>> out;
  for (std::size_t m = 0; m < members_.size(); ++m)
    out.emplace_back(members_[m].first, memberSamplers_[m]->valueAt(latDeg, lonDeg));
  return out;
}

}  // namespace atmoglobe::engine
