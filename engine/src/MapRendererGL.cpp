#include <atmoglobe/engine/MapRendererGL.h>
#include <atmoglobe/engine/ShaderConstants.h>

#include "LoaderGL.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Horizon.h>
#include <atmoglobe/map/MapLod.h>
#include <atmoglobe/map/VectorFile.h>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>

namespace atmoglobe::engine {

struct MapRendererGL::ChunkGL {
  GLuint vbo = 0;
  GLsizei segments = 0;
  glm::dvec3 originEcef{0.0};
  std::size_t bytes = 0;
  std::uint64_t lastFrame = 0;
  ~ChunkGL() {
    if (vbo) glDeleteBuffers(1, &vbo);
  }
};

namespace {
constexpr std::size_t kChunkBudgetBytes = 256u << 20;
constexpr std::size_t kPiecePoints = 256;  // user lines are cut into pieces of at most this many points

std::unique_ptr<MapRendererGL::ChunkGL> uploadChunk(const map::LineChunk& c) {
  auto chunk = std::make_unique<MapRendererGL::ChunkGL>();
  chunk->originEcef = c.originEcef;
  chunk->segments = static_cast<GLsizei>(c.segmentCount());
  chunk->bytes = c.vertices.size() * sizeof(float);
  if (chunk->segments > 0) {
    glCreateBuffers(1, &chunk->vbo);
    glNamedBufferStorage(chunk->vbo, static_cast<GLsizeiptr>(chunk->bytes), c.vertices.data(), 0);
  }
  return chunk;
}

// x - hi, narrowed; not inlined for the reason in map/src/GeoLines.cpp (GCC 12 SLP bug).
[[gnu::noinline]] float lowPartOf(double x, float hi) { return static_cast<float>(x - static_cast<double>(hi)); }

glm::dvec3 surface(double lonDeg, double latDeg, double heightMeters = 0.0) {
  return globe::geodeticToEcef({std::clamp(latDeg, -90.0, 90.0), lonDeg, heightMeters});
}
}  // namespace

Result<std::unique_ptr<MapRendererGL>> MapRendererGL::create(const std::string& gshhgDir) {
  auto program = ShaderProgramGL::create("map_line.vert", "map_line.frag", ellipsoidShaderDefines());
  if (!program) return program.forwardError();
  std::unique_ptr<MapRendererGL> r(new MapRendererGL());
  r->program_ = std::move(*program);
  r->gshhgDir_ = gshhgDir;
  glCreateVertexArrays(1, &r->vao_);
  for (GLuint a = 0; a < 4; ++a) {
    glEnableVertexArrayAttrib(r->vao_, a);
    glVertexArrayAttribFormat(r->vao_, a, 3, GL_FLOAT, GL_FALSE, a * 3 * sizeof(float));
    glVertexArrayAttribBinding(r->vao_, a, 0);
  }
  glVertexArrayBindingDivisor(r->vao_, 0, 1);  // one segment (two points) per instance
  // Forecaster defaults: coastlines and country borders light, states thinner and greyer.
  r->builtinStyle_[0] = {glm::vec3(0.72f, 0.86f, 0.95f), 1.4f, 0.9f};
  r->builtinStyle_[1] = {glm::vec3(1.0f, 1.0f, 1.0f), 1.6f, 0.95f};
  r->builtinStyle_[2] = {glm::vec3(0.82f, 0.82f, 0.82f), 1.0f, 0.75f};
  return r;
}

MapRendererGL::~MapRendererGL() {
  chunks_.clear();
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

const map::GshhgFile* MapRendererGL::file(map::GshhgKind kind, map::GshhgResolution r) {
  const auto key = std::make_pair(static_cast<int>(kind), static_cast<int>(r));
  if (auto it = files_.find(key); it != files_.end()) return it->second.get();
  if (fileFailed_.count(key)) return nullptr;
  auto f = map::GshhgFile::open(map::gshhgPath(gshhgDir_, kind, r), kind);
  if (!f) {
    std::fprintf(stderr, "map context: %s\n", f.error().c_str());
    fileFailed_[key] = true;
    return nullptr;
  }
  return (files_[key] = std::move(*f)).get();
}

Status MapRendererGL::setBuiltinLayers(bool enabled) {
  builtin_ = false;
  if (!enabled) return Ok{};
  for (map::GshhgKind kind : {map::GshhgKind::Shoreline, map::GshhgKind::Border}) {
    auto f = map::GshhgFile::open(map::gshhgPath(gshhgDir_, kind, map::GshhgResolution::Crude), kind);
    if (!f) return makeError("map context: " + f.error());
  }
  builtin_ = true;
  return Ok{};
}

void MapRendererGL::addLines(const std::vector<map::GeoPolyline>& lines, const MapLineStyle& style) {
  Overlay o;
  o.style = style;
  std::map<int, std::size_t> groupOfCell;
  for (const map::GeoPolyline& line : lines) {
    for (const map::GeoPolyline& part : map::splitAtAntimeridian(line)) {
      for (std::size_t start = 0; start + 1 < part.lonLatDeg.size(); start += kPiecePoints - 1) {
        map::GeoPolyline piece;
        const std::size_t end = std::min(part.lonLatDeg.size(), start + kPiecePoints);
        piece.lonLatDeg.assign(part.lonLatDeg.begin() + static_cast<std::ptrdiff_t>(start),
                               part.lonLatDeg.begin() + static_cast<std::ptrdiff_t>(end));
        // Grouped by the 20-degree cell of the first point: one chunk (one draw) per cell.
        const glm::dvec2 p = piece.lonLatDeg.front();
        const int cell = static_cast<int>(std::floor((p.x + 180.0) / 20.0)) * 16 +
                         std::clamp(static_cast<int>(std::floor((p.y + 90.0) / 20.0)), 0, 8);
        auto [it, added] = groupOfCell.emplace(cell, o.pieces.size());
        if (added) o.pieces.emplace_back();
        o.pieces[it->second].push_back(std::move(piece));
      }
    }
  }
  for (const auto& group : o.pieces) {
    // Bounding sphere of the group's points, padded by the sag of its longest segment.
    glm::dvec3 lo(1e300), hi(-1e300);
    double longest = 0.0;
    std::vector<glm::dvec3> pts;
    for (const auto& piece : group) {
      for (std::size_t i = 0; i < piece.lonLatDeg.size(); ++i) {
        pts.push_back(surface(piece.lonLatDeg[i].x, piece.lonLatDeg[i].y));
        lo = glm::min(lo, pts.back());
        hi = glm::max(hi, pts.back());
        if (i > 0) longest = std::max(longest, glm::distance(pts.back(), pts[pts.size() - 2]));
      }
    }
    const glm::dvec3 c = 0.5 * (lo + hi);
    double r = 0.0;
    for (const glm::dvec3& p : pts) r = std::max(r, glm::distance(p, c));
    o.spheres.emplace_back(c, r + map::chordSagMeters(longest) + 1.0);
  }
  overlays_.push_back(std::move(o));
}

void MapRendererGL::clearLines() {
  overlays_.clear();
  for (auto it = chunks_.begin(); it != chunks_.end();) {
    if (std::get<0>(it->first) >= 3) {  // overlay chunks (0..2 are the built-in layers)
      chunkBytes_ -= it->second->bytes;
      it = chunks_.erase(it);
    } else {
      ++it;
    }
  }
}

Result<std::string> MapRendererGL::addOverlay(const std::string& path, const MapLineStyle& style) {
  auto contents = map::readVectorFile(path);
  if (!contents) return contents.forwardError();
  addLines(contents->lines, style);
  std::size_t points = 0;
  for (const auto& l : contents->lines) points += l.lonLatDeg.size();
  std::string crs;
  for (const std::string& c : contents->layerCrs) crs += (crs.empty() ? "" : ", ") + c;
  char line[256];
  std::snprintf(line, sizeof line, "%zu features: %zu lines, %zu polygon rings, %zu points; CRS ", contents->features,
                contents->lineStrings, contents->rings, points);
  return std::string(line) + crs;
}

bool MapRendererGL::binVisible(const Camera& camera, const globe::ViewState& view, const map::GshhgBinBox& box) const {
  // 5 x 5 samples over the bin; the surface between samples bulges past their hull by at most
  // the sag of the sample spacing, which pads the sphere and lifts the horizon samples.
  constexpr int n = 5;
  const double stepDeg = (box.eastDeg - box.westDeg) / (n - 1);
  const double pad = map::chordSagMeters(stepDeg * 111320.0 * 1.5) + 1.0;
  const glm::dvec3 center = surface(0.5 * (box.westDeg + box.eastDeg), 0.5 * (box.southDeg + box.northDeg));
  glm::dvec3 samples[n * n];
  double radius = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      samples[j * n + i] = surface(box.westDeg + i * stepDeg, box.southDeg + j * stepDeg, pad);
      radius = std::max(radius, glm::distance(samples[j * n + i], center));
    }
  radius += pad;
  for (const glm::dvec4& plane : view.frustumPlanesEcef)
    if (glm::dot(glm::dvec3(plane), center) + plane.w < -radius) return false;
  for (const glm::dvec3& s : samples)
    if (!globe::isOccludedByEllipsoid(camera.eyeEcef(), s)) return true;
  return false;
}

void setEyeRelativeUniformsGL(const ShaderProgramGL& program, const glm::dvec3& eyeEcef, const glm::dvec3& originEcef) {
  const glm::dvec3 eyeRel = eyeEcef - originEcef;
  const glm::vec3 eyeHi(eyeRel);
  glm::vec3 eyeLo;
  for (int k = 0; k < 3; ++k) eyeLo[k] = lowPartOf(eyeRel[k], eyeHi[k]);
  glUniform3fv(program.uniform("u_eyeHi"), 1, glm::value_ptr(eyeHi));
  glUniform3fv(program.uniform("u_eyeLo"), 1, glm::value_ptr(eyeLo));
  const glm::dvec3 invRadii(1.0 / globe::kWgs84A, 1.0 / globe::kWgs84A, 1.0 / globe::kWgs84B);
  glUniform3fv(program.uniform("u_invRadii"), 1, glm::value_ptr(glm::vec3(invRadii)));
  glUniform3fv(program.uniform("u_originScaled"), 1, glm::value_ptr(glm::vec3(originEcef * invRadii)));
}

void beginOverGlobeGL() {
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
}

void endOverGlobeGL() {
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
}

void MapRendererGL::drawChunk(const Camera& camera, const ChunkGL& chunk, const MapLineStyle& style) {
  if (chunk.segments == 0) return;
  setEyeRelativeUniformsGL(program_, camera.eyeEcef(), chunk.originEcef);
  glUniform1f(program_.uniform("u_halfWidthPx"), 0.5f * style.widthPx);
  glUniform4f(program_.uniform("u_color"), style.color.r, style.color.g, style.color.b, style.opacity);
  glVertexArrayVertexBuffer(vao_, 0, chunk.vbo, 0, 12 * sizeof(float));
  glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, chunk.segments);
}

// One chunk a frame wants at a resolution: its cache key, how to make it and its style.
struct MapRendererGL::Wanted {
  std::tuple<int, int, int> key;
  std::function<std::unique_ptr<ChunkGL>()> build;
  const MapLineStyle* style = nullptr;
};

namespace {
// The eye's distance (m) to the nearest point of a bin, approximately: to the point of the box
// nearest the eye's sub-point in latitude and longitude (on a meridian edge the true nearest
// point lies a little poleward: a few percent nearer in the worst case, well within the factor
// of 5 between the levels' point spacings), never less than the eye's height.
double binDistanceMeters(const glm::dvec3& eyeEcef, const globe::Geodetic& eye, const map::GshhgBinBox& box) {
  const double halfLon = 0.5 * (box.eastDeg - box.westDeg);
  const double midLon = box.westDeg + halfLon;
  const double dLon = std::remainder(eye.lonDeg - midLon, 360.0);
  const double lon = midLon + std::clamp(dLon, -halfLon, halfLon);
  const double lat = std::clamp(eye.latDeg, box.southDeg, box.northDeg);
  return std::max(std::abs(eye.heightMeters), glm::distance(eyeEcef, surface(lon, lat)));
}
}  // namespace

map::GshhgResolution MapRendererGL::levelAt(const Camera& camera, double distanceMeters) {
  return map::gshhgResolutionForScale(distanceMeters / camera.focalLengthPx());
}

std::vector<MapRendererGL::Wanted> MapRendererGL::wantedChunks(const Camera& camera, const globe::ViewState& view,
                                                               MapFrameStats* stats) {
  std::vector<Wanted> wanted;
  const glm::dvec3 eyeEcef = camera.eyeEcef();
  const globe::Geodetic eye = globe::ecefToGeodetic(eyeEcef);
  if (builtin_) {
    // Each part of the view at the level its distance asks for (the level whose published point
    // spacing is at most two pixels there): bins nest, 20 (crude) > 10 (low) > 5 (intermediate)
    // and 10 > 2 (high) > 1 (full) degrees, so a bin is drawn whole at the level of its nearest
    // point or handed to the finer bins inside it, and no part of the view is drawn twice.
    using R = map::GshhgResolution;
    std::vector<std::pair<R, int>> bins;  // (level, bin of that level's files)
    // False when the level's files are missing (the coarser bin is drawn instead).
    const auto gather = [&](R res, const map::GshhgBinBox& box, const auto& self) -> bool {
      const map::GshhgFile* shore = file(map::GshhgKind::Shoreline, res);
      const map::GshhgFile* border = file(map::GshhgKind::Border, res);
      if (!shore && !border) return false;
      const map::GshhgFile& f = shore ? *shore : *border;
      for (int b : f.binsInside(box)) {
        const map::GshhgBinBox bb = f.binBox(b);
        if (!binVisible(camera, view, bb)) continue;
        const R need = std::max(res, levelAt(camera, binDistanceMeters(eyeEcef, eye, bb)));
        // The finer bins inside: low in crude, intermediate or high in low (5 and 2 deg do not
        // nest), full in high; intermediate bins hold no whole high ones.
        R finer = res;
        if (res == R::Crude) finer = R::Low;
        if (res == R::Low) finer = need == R::Intermediate ? R::Intermediate : R::High;
        if (res == R::High) finer = R::Full;
        if (need == res || finer == res || !self(finer, bb, self)) bins.emplace_back(res, b);
      }
      return true;
    };
    gather(R::Crude, map::GshhgBinBox{-180.0, -90.0, 180.0, 90.0}, gather);
    if (stats) {
      stats->binsInView = static_cast<int>(bins.size());
      for (const auto& [res, b] : bins) {
        stats->resolution = std::max(stats->resolution, res);
        ++stats->binsAtLevel[static_cast<std::size_t>(res)];
      }
    }
    for (const auto& [res, b] : bins) {
      const map::GshhgFile* shore = file(map::GshhgKind::Shoreline, res);
      const map::GshhgFile* border = file(map::GshhgKind::Border, res);
      const struct {
        const map::GshhgFile* file;
        unsigned levels;
      } layers[3] = {
          {shore, map::kCoastLevels}, {border, map::kNationalBorderLevels}, {border, map::kStateBorderLevels}};
      const double maxSegment = map::maxSegmentMetersFor(res);
      for (int layer = 0; layer < 3; ++layer) {
        if (!layers[layer].file) continue;
        // State/province borders clutter whole-hemisphere views: shown from the low level down.
        if (layer == 2 && res == R::Crude) continue;
        const map::GshhgFile* f = layers[layer].file;
        const unsigned levels = layers[layer].levels;
        wanted.push_back({{layer, static_cast<int>(res), b},
                          [f, b, levels, maxSegment]() -> std::unique_ptr<ChunkGL> {
                            auto lines = f->readBin(b, levels);
                            if (!lines) {
                              std::fprintf(stderr, "map context: %s\n", lines.error().c_str());
                              return std::make_unique<ChunkGL>();  // empty: not retried every frame
                            }
                            return uploadChunk(map::buildLineChunk(*lines, maxSegment));
                          },
                          &builtinStyle_[layer]});
      }
    }
  }
  for (std::size_t o = 0; o < overlays_.size(); ++o) {
    const Overlay& overlay = overlays_[o];
    for (std::size_t g = 0; g < overlay.pieces.size(); ++g) {
      const glm::dvec4& sphere = overlay.spheres[g];
      bool outside = false;
      for (const glm::dvec4& plane : view.frustumPlanesEcef)
        outside = outside || glm::dot(glm::dvec3(plane), glm::dvec3(sphere)) + plane.w < -sphere.w;
      if (outside) continue;
      // Densified for the nearest point of the group's sphere (the chord sag: maxSegmentMetersFor).
      const double nearest =
          std::max(std::abs(eye.heightMeters), glm::distance(eyeEcef, glm::dvec3(sphere)) - sphere.w);
      const map::GshhgResolution res = levelAt(camera, nearest);
      const double maxSegment = map::maxSegmentMetersFor(res);
      const std::vector<map::GeoPolyline>* piece = &overlay.pieces[g];
      wanted.push_back({{3 + static_cast<int>(o), static_cast<int>(res), static_cast<int>(g)},
                        [piece, maxSegment] { return uploadChunk(map::buildLineChunk(*piece, maxSegment)); },
                        &overlay.style});
    }
  }
  return wanted;
}

MapFrameStats MapRendererGL::draw(const Camera& camera) {
  MapFrameStats stats;
  ++frame_;
  lastFrameComplete_ = true;
  if (!builtin_ && overlays_.empty()) return stats;
  const globe::ViewState view = camera.viewState();
  std::vector<Wanted> wanted = wantedChunks(camera, view, &stats);

  // Missing chunks are read and built (GSHHG bins, geodesic densification, upload): all of them
  // without a budget (render, the first frame), else while the budget lasts. Until every chunk of
  // the view is made, the chunks of the last complete view stay (as cached), so a flight that
  // changes levels does not stall on the new level's reads.
  const auto t0 = std::chrono::steady_clock::now();
  const bool unbounded = buildBudgetMs_ <= 0.0 || !shownValid_;
  bool missing = false, builtOne = false;
  for (const Wanted& w : wanted) {
    if (chunks_.count(w.key)) continue;
    // At least one chunk a frame, so that a view is completed however slow the machine.
    if (!unbounded && builtOne &&
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() >= buildBudgetMs_) {
      missing = true;
      continue;
    }
    builtOne = true;
    std::unique_ptr<ChunkGL> c = w.build();
    if (!c) continue;
    chunkBytes_ += c->bytes;
    ++stats.chunksBuilt;
    chunks_.emplace(w.key, std::move(c));
  }
  if (missing) {
    lastFrameComplete_ = false;
  } else {
    shown_.clear();
    for (const Wanted& w : wanted) shown_.push_back(w.key);
    shownValid_ = true;
  }

  program_.use();
  const glm::mat4 viewProjection(camera.modelViewProjectionRelativeTo(camera.eyeEcef()));
  glUniformMatrix4fv(program_.uniform("u_viewProjection"), 1, GL_FALSE, glm::value_ptr(viewProjection));
  glUniform2f(program_.uniform("u_viewportPx"), static_cast<float>(camera.widthPx()),
              static_cast<float>(camera.heightPx()));
  glUniform1f(program_.uniform("u_depthLift"), kMapDepthLift);
  beginOverGlobeGL();
  glBindVertexArray(vao_);
  for (const ChunkKey& key : shown_) {
    auto it = chunks_.find(key);
    if (it == chunks_.end()) continue;  // dropped (a layer removed)
    // The style by the key's layer (an overlay's may have gone since the view was complete).
    const int layer = std::get<0>(key);
    if (layer >= 3 && static_cast<std::size_t>(layer - 3) >= overlays_.size()) continue;
    const MapLineStyle& style = layer < 3 ? builtinStyle_[layer] : overlays_[static_cast<std::size_t>(layer - 3)].style;
    it->second->lastFrame = frame_;
    if (it->second->segments > 0) {
      drawChunk(camera, *it->second, style);
      ++stats.chunksDrawn;
      stats.segmentsDrawn += static_cast<std::size_t>(it->second->segments);
    }
  }
  glBindVertexArray(0);
  endOverGlobeGL();
  // Over budget: drop what this frame did not use.
  if (chunkBytes_ > kChunkBudgetBytes) {
    for (auto it = chunks_.begin(); it != chunks_.end();) {
      if (it->second->lastFrame != frame_) {
        chunkBytes_ -= it->second->bytes;
        it = chunks_.erase(it);
      } else {
        ++it;
      }
    }
  }
  return stats;
}

}  // namespace atmoglobe::engine
