// A forecast grid on the GPU (GridVolumeGL.h).
#include <atmoglobe/engine/GridVolumeGL.h>

#include "LoaderGL.h"

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <glm/gtc/type_ptr.hpp>

#include <atmoglobe/volume/Decimate.h>
#include <atmoglobe/volume/GridLevelIndex.h>
#include <atmoglobe/volume/StepCache.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

namespace atmoglobe::engine {
namespace {

constexpr int kLookupEntries = 4096;  // per axis of a rectilinear grid's tables

}  // namespace

Result<std::unique_ptr<GridVolumeGL>> GridVolumeGL::create(const volume::GridVolume& grid) {
  if (auto st = checkDrawable(grid); !st) return st.forwardError();
  return create(prepare(grid));
}

Status GridVolumeGL::checkDrawable(const volume::GridVolume& grid) {
  if (grid.nx < 2 || grid.ny < 2 || grid.nz < 2)
    return makeError((grid.path.empty() ? std::string("grid") : grid.path) + ": " + grid.variable +
                     ": a grid needs at least 2 columns, rows and levels to be drawn (has " + std::to_string(grid.nx) +
                     " x " + std::to_string(grid.ny) + " x " + std::to_string(grid.nz) + ")");
  return Ok{};
}

Result<std::unique_ptr<GridVolumeGL>> GridVolumeGL::create(std::shared_ptr<const Prepared> prepared) {
  const std::string name = prepared->grid->path.empty() ? std::string("grid") : prepared->grid->path;
  // A grid the GPU cannot hold (its 3-D texture size, GL_OUT_OF_MEMORY, or the artificial limit
  // $ATMOGLOBE_MAX_TEXTURE_BYTES) is drawn at half the resolution, and so on, with a warning.
  GLint max3d = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
  const std::shared_ptr<const volume::GridVolume> whole = prepared->grid;
  for (int halvings = 0;; ++halvings) {
    std::string tooLarge;
    auto gl = upload(prepared, name, &tooLarge);
    if (gl && halvings > 0) (*gl)->unreduced_ = whole;
    if (gl || tooLarge.empty()) return gl;
    const volume::GridVolume& g = *prepared->grid;
    if (halvings == kMaxHalvings || g.nx < 4 || g.ny < 4)
      return makeError(name + ": " + g.variable + ": " + tooLarge + ", even at 1/" + std::to_string(1 << halvings) +
                       " of the resolution (crop the grid)");
    volume::GridVolume reduced = volume::decimateGrid(g, 2, static_cast<long>(g.nz) > max3d);
    std::cerr << "atmoglobe: warning: " << name << ": " << g.variable << ": " << tooLarge
              << "; drawn at lower resolution, " << reduced.nx << " x " << reduced.ny << " x " << reduced.nz
              << " (every 2nd column and row" << (reduced.nz < g.nz ? " and level" : "") << ")\n";
    prepared = prepare(reduced);
  }
}

std::uint64_t GridVolumeGL::Prepared::bytes() const {
  return volume::gridVolumeBytes(*grid) + texels.capacity() * sizeof(glm::vec2) + lookup.capacity() * sizeof(float) +
         (occupancy.maxValues.capacity() + occupancy.blockMaxValues.capacity()) * sizeof(float);
}

std::shared_ptr<const GridVolumeGL::Prepared> GridVolumeGL::prepare(const volume::GridVolume& grid) {
  auto pr = std::make_shared<Prepared>();
  pr->grid = std::make_shared<const volume::GridVolume>(grid);
  pr->sampler = std::make_shared<const volume::GridSampler>(*pr->grid);
  const volume::GridVolume& g = *pr->grid;
  const volume::GridSampler& s = *pr->sampler;
  const bool wraps = g.wrapsLongitude && !g.curvilinear;
  const bool caps = s.hasPoleCaps();
  // The textures hold the grid closed as the sampler samples it (the copy of column 0, the poles).
  pr->rowOffset = s.closedRowOffset();
  pr->textureSize = s.closedSize();
  pr->origin = s.boundingSphere().centreEcef;
  const int nx = static_cast<int>(g.nx), ny = static_cast<int>(g.ny);

  // Values and heights: RG32F (value or GPU_NO_DATA, height above the ellipsoid). Not NaN: GLSL
  // compilers may optimise NaN tests away.
  const glm::ivec3 ts = pr->textureSize;
  std::vector<glm::vec2>& texels = pr->texels;
  texels.resize(static_cast<std::size_t>(ts.x) * ts.y * ts.z);
  for (int k = 0; k < ts.z; ++k)
    for (int tr = 0; tr < ts.y; ++tr)
      for (int tc = 0; tc < ts.x; ++tc) {
        // A reduced row's padding: no data, and the height of the row's last closed column (the
        // shader may fetch it with weight 0; 0 x NaN would be NaN).
        const float v = s.columnValue(s.closedColumn(tc, tr), static_cast<std::size_t>(k));
        texels[(static_cast<std::size_t>(k) * ts.y + tr) * ts.x + tc] =
            glm::vec2(std::isfinite(v) ? v : MarchConstants::kNoData,
                      static_cast<float>(s.columnHeight(s.closedHeightColumn(tc, tr), static_cast<std::size_t>(k))));
      }
  // Lookup tables, computed by the CPU sampler's own horizontalIndex (exact at the entries).
  if (g.reduced()) {
    // R32F, 4 rows of max(kLookupEntries, closed rows) texels: row 1 the latitude table (as a
    // rectilinear grid's); rows 0, 2, 3 at x = closed row: its closed columns, first longitude and
    // spacing (the row table). The column index's reference axis in lonRange.
    const double latStart = caps ? -90.0 : g.latDeg[0];
    const double latSpan = (caps ? 90.0 : g.latDeg[g.ny - 1]) - latStart;
    const int w = std::max(kLookupEntries, ts.y);
    pr->lonRange = glm::vec2(static_cast<float>(s.reducedWestDeg()), static_cast<float>(s.reducedSpacingDeg()));
    pr->latRange = glm::vec2(static_cast<float>(latStart), static_cast<float>(latSpan));
    pr->lookupSize = glm::ivec2(w, 4);
    std::vector<float>& table = pr->lookup;
    table.assign(4 * static_cast<std::size_t>(w), 0.0f);
    for (int e = 0; e < w; ++e) {
      const double lat = std::clamp(latStart + static_cast<double>(e) / (w - 1) * latSpan, -90.0, 90.0);
      table[static_cast<std::size_t>(w) + e] = static_cast<float>(s.rowIndex(lat).value_or(0.0) + pr->rowOffset);
    }
    for (int tr = 0; tr < ts.y; ++tr) {
      const volume::GridSampler::ClosedRow row = s.closedRow(tr);
      table[static_cast<std::size_t>(tr)] = static_cast<float>(row.columns);
      table[2 * static_cast<std::size_t>(w) + tr] = static_cast<float>(row.firstLonDeg);
      table[3 * static_cast<std::size_t>(w) + tr] = static_cast<float>(row.spacingDeg);
    }
  } else if (!g.curvilinear) {
    const double lonStart = g.lonDeg[0];
    const double lonSpan = wraps ? 360.0 : g.lonDeg[g.nx - 1] - g.lonDeg[0];
    const double latStart = caps ? -90.0 : g.latDeg[0];
    const double latSpan = (caps ? 90.0 : g.latDeg[g.ny - 1]) - latStart;
    pr->lonRange = glm::vec2(static_cast<float>(lonStart), static_cast<float>(lonSpan));
    pr->latRange = glm::vec2(static_cast<float>(latStart), static_cast<float>(latSpan));
    pr->lookupSize = glm::ivec2(kLookupEntries, 2);
    std::vector<float>& table = pr->lookup;
    table.assign(2 * kLookupEntries, 0.0f);
    for (int e = 0; e < kLookupEntries; ++e) {
      const double f = static_cast<double>(e) / (kLookupEntries - 1);
      const double lon = lonStart + f * lonSpan;
      const auto ijLon = s.horizontalIndex(g.latDeg[0], lon);
      // The last entry of a wrapping grid is column nx (the copy of column 0), not 0.
      table[e] = wraps && e == kLookupEntries - 1
                     ? static_cast<float>(g.nx)
                     : static_cast<float>(ijLon ? ijLon->x : static_cast<double>(g.nx - 1));
      const double lat = std::clamp(latStart + f * latSpan, -90.0, 90.0);
      const auto ijLat = s.horizontalIndex(lat, g.lonDeg[0]);
      table[kLookupEntries + e] = static_cast<float>((ijLat ? ijLat->y : 0.0) + pr->rowOffset);
    }
  } else {
    const auto [lonMinIt, lonMaxIt] = std::minmax_element(g.lonDeg.begin(), g.lonDeg.end());
    const auto [latMinIt, latMaxIt] = std::minmax_element(g.latDeg.begin(), g.latDeg.end());
    double lonMin = *lonMinIt, lonMax = *lonMaxIt, latMin = *latMinIt, latMax = *latMaxIt;
    // A grid around a pole (the sampler finds the pole inside it): the table reaches the pole
    // and takes every longitude.
    const bool north = s.horizontalIndex(90.0, 0.0).has_value(), south = s.horizontalIndex(-90.0, 0.0).has_value();
    if (north) latMax = 90.0;
    if (south) latMin = -90.0;
    if (north || south || lonMax - lonMin > 180.0) {
      lonMin = -180.0;
      lonMax = 180.0;
    }
    pr->lonRange = glm::vec2(static_cast<float>(lonMin), static_cast<float>(lonMax - lonMin));
    pr->latRange = glm::vec2(static_cast<float>(latMin), static_cast<float>(latMax - latMin));
    const int w = std::clamp(4 * nx, 2, 2048), h = std::clamp(4 * ny, 2, 2048);
    pr->lookupSize = glm::ivec2(w, h);
    pr->lookup.assign(2 * static_cast<std::size_t>(w) * h, 0.0f);
    auto* table = reinterpret_cast<glm::vec2*>(pr->lookup.data());  // RG pairs
    for (int b = 0; b < h; ++b)
      for (int a = 0; a < w; ++a) {
        const double lat = latMin + (latMax - latMin) * b / (h - 1);
        const double lon = lonMin + (lonMax - lonMin) * a / (w - 1);
        const auto ij = s.horizontalIndex(lat, lon);
        table[static_cast<std::size_t>(b) * w + a] = ij ? glm::vec2(*ij) : glm::vec2(-1.0e6f);
      }
  }

  // The level lookup (volume::GridLevelIndex): its brackets in slices after the levels, 4 bins per
  // texel, and its height-to-bin map as one more row of the lookup texture (entries: its width).
  {
    const volume::GridLevelIndex index = volume::buildGridLevelIndex(s, pr->lookupSize.x);
    pr->levelSlices = (index.bins + 3) / 4;
    const std::size_t slice = static_cast<std::size_t>(ts.x) * ts.y;
    texels.resize(slice * (static_cast<std::size_t>(ts.z) + pr->levelSlices), glm::vec2(0.0f));
    for (int tr = 0; tr < ts.y; ++tr)
      for (int tc = 0; tc < ts.x; ++tc) {
        const std::size_t cell = static_cast<std::size_t>(tr) * ts.x + tc;
        for (int b = 0; b < index.bins; ++b) {
          const std::size_t i = cell * index.bins + b;
          const int code = index.loMin[i] | (index.span[i] << 8);  // 12 bits
          glm::vec2& t = texels[(static_cast<std::size_t>(ts.z) + b / 4) * slice + cell];
          float& pair = (b & 2) == 0 ? t.x : t.y;
          pair += static_cast<float>((b & 1) == 0 ? code : code * 4096);  // exact: < 2^24
        }
      }
    const int w = pr->lookupSize.x, h = pr->lookupSize.y;
    const int channels = g.curvilinear ? 2 : 1;
    pr->lookup.resize(static_cast<std::size_t>(channels) * w * (h + 1), 0.0f);
    for (int e = 0; e < w; ++e)
      pr->lookup[(static_cast<std::size_t>(h) * w + e) * channels] = index.referenceLevelAtHeight[std::min<std::size_t>(
          static_cast<std::size_t>(e), index.referenceLevelAtHeight.size() - 1)];
    const double span = index.maxHeightMeters - index.minHeightMeters;
    pr->levelMap = glm::vec4(static_cast<float>(index.minHeightMeters),
                             span > 0.0 ? static_cast<float>((index.heightEntries() - 1) / span) : 0.0f,
                             static_cast<float>(index.binsPerLevel), static_cast<float>(index.bins));
  }

  // Empty-space grid: built in volume from the same closed columns (its origin is pr->origin).
  pr->occupancy = volume::buildOccupancyGrid(s);
  return pr;
}

Result<std::unique_ptr<GridVolumeGL>> GridVolumeGL::upload(const std::shared_ptr<const Prepared>& pr,
                                                           const std::string& name, std::string* tooLarge) {
  const volume::GridVolume& g = *pr->grid;
  std::unique_ptr<GridVolumeGL> gl(new GridVolumeGL());
  gl->grid_ = pr->grid;
  gl->sampler_ = pr->sampler;
  gl->origin_ = pr->origin;
  gl->textureSize_ = pr->textureSize;
  gl->rowOffset_ = pr->rowOffset;
  gl->lonRange_ = pr->lonRange;
  gl->latRange_ = pr->latRange;
  gl->lookupSize_ = pr->lookupSize;
  gl->levelSlices_ = pr->levelSlices;
  gl->levelMap_ = pr->levelMap;
  GLint max3d = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
  const glm::ivec3 ts = pr->textureSize + glm::ivec3(0, 0, pr->levelSlices);  // the levels, then the brackets
  const std::size_t textureBytes = pr->texels.size() * sizeof(glm::vec2);
  const std::string shape = std::to_string(g.nx) + " x " + std::to_string(g.ny) + " x " + std::to_string(g.nz);
  if (ts.x > max3d || ts.y > max3d || ts.z > max3d) {
    *tooLarge = shape + " exceeds the GPU's 3-D texture size " + std::to_string(max3d);
    return makeError(name + ": " + *tooLarge);
  }
  if (const std::size_t limit = textureByteLimit(); limit > 0 && textureBytes > limit) {
    *tooLarge = shape + " needs a " + megabytes(textureBytes) + " texture, over the GPU memory limit " +
                megabytes(limit) + " ($ATMOGLOBE_MAX_TEXTURE_BYTES)";
    return makeError(name + ": " + *tooLarge);
  }
  // Values and heights: RG32F (value or GPU_NO_DATA, height above the ellipsoid).
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl->values_ = makeVolumeTextureGL(GL_TEXTURE_3D);
  clearErrorsGL();
  glTextureStorage3D(gl->values_, 1, GL_RG32F, ts.x, ts.y, ts.z);
  if (outOfMemoryGL()) {
    *tooLarge = shape + ": the GPU is out of memory (GL_OUT_OF_MEMORY) for its " + megabytes(textureBytes) + " texture";
    return makeError(name + ": " + *tooLarge);  // ~GridVolumeGL deletes the texture
  }
  glTextureSubImage3D(gl->values_, 0, 0, 0, 0, ts.x, ts.y, ts.z, GL_RG, GL_FLOAT, pr->texels.data());
  gl->gpuBytes_ = textureBytes;
  // Lookup tables: R32F rows (rectilinear: longitude, latitude) or an RG32F raster (curvilinear).
  gl->lookup_ = makeVolumeTextureGL(GL_TEXTURE_2D);
  const glm::ivec2 ls = pr->lookupSize;
  glTextureStorage2D(gl->lookup_, 1, g.curvilinear ? GL_RG32F : GL_R32F, ls.x, ls.y + 1);  // + the level map
  glTextureSubImage2D(gl->lookup_, 0, 0, 0, ls.x, ls.y + 1, g.curvilinear ? GL_RG : GL_RED, GL_FLOAT,
                      pr->lookup.data());
  gl->gpuBytes_ += pr->lookup.size() * sizeof(float);
  gl->occupancy_ = OccupancyGridGL(pr->occupancy);
  return gl;
}

GridVolumeGL::~GridVolumeGL() {
  for (GLuint t : {values_, lookup_})
    if (t) glDeleteTextures(1, &t);
}

std::vector<std::string> GridVolumeGL::samplerDefines(const VolumeRenderOptions& options) const {
  return {std::string("INTERPOLATION ") + (options.render.interpolation == volume::Interpolation::Nearest ? "0" : "1"),
          std::string("CURVILINEAR ") + (grid_->curvilinear ? "1" : "0"),
          std::string("WRAPS ") + (grid_->wrapsLongitude && !grid_->curvilinear ? "1" : "0"),
          std::string("REDUCED ") + (grid_->reduced() ? "1" : "0")};
}

void GridVolumeGL::setSamplerUniforms(const SamplerBindingGL& b) const {
  UniformCacheGL& u = *b.uniforms;
  const std::string& p = b.prefix;
  auto name = [&](const char* n) { return std::string(p).append(n); };
  const volume::BoundingSphere sphere = sampler_->boundingSphere();
  glUniform3fv(u(name("origin")), 1, glm::value_ptr(glm::vec3(origin_)));
  glUniform4f(u(name("sphere")), static_cast<float>(sphere.centreEcef.x - origin_.x),
              static_cast<float>(sphere.centreEcef.y - origin_.y), static_cast<float>(sphere.centreEcef.z - origin_.z),
              static_cast<float>(sphere.radiusMeters));
  glUniform1f(u(name("outerRadius")),
              static_cast<float>(globe::kWgs84A + std::max(0.0, sampler_->maxHeightMeters()) + 1.0));
  glUniform2f(u(name("heightRange")), static_cast<float>(sampler_->minHeightMeters()),
              static_cast<float>(sampler_->maxHeightMeters()));
  glUniform4f(u(name("lonLat")), lonRange_.x, lonRange_.y, latRange_.x, latRange_.y);
  glUniform2iv(u(name("lookupSize")), 1, glm::value_ptr(lookupSize_));
  glUniform3iv(u(name("texSize")), 1, glm::value_ptr(textureSize_));
  glUniform4fv(u(name("levelMap")), 1, glm::value_ptr(levelMap_));
  glUniform1i(u(name("rowOffset")), rowOffset_);
  // The step rule's cell scale (volume::CellScale; no table: zeros, the fixed step).
  const volume::CellScale& cs = sampler_->cellScale();
  std::vector<float> spacing(volume::CellScale::kEntries, 0.0f);
  for (std::size_t e = 0; e < cs.levelSpacingMeters.size() && e < spacing.size(); ++e)
    spacing[e] = static_cast<float>(cs.levelSpacingMeters[e]);
  glUniform4f(u(name("cellScale")), cs.levelSpacingMeters.empty() ? 0.0f : static_cast<float>(cs.columnSpacingMeters),
              static_cast<float>(cs.minHeightMeters), static_cast<float>(cs.entriesPerMeter), 0.0f);
  glUniform1fv(u(name("levelSpacing")), volume::CellScale::kEntries, spacing.data());
  // The reference of the shader's small-angle geodetic conversion: the grid's centre.
  const globe::Geodetic ref = sphere.centreEcef == glm::dvec3(0.0) ? globe::Geodetic{0.0, 0.0, 0.0}
                                                                   : globe::ecefToGeodetic(sphere.centreEcef);
  const double la = degreesToRadians(ref.latDeg), lo = degreesToRadians(ref.lonDeg);
  glUniform4f(u(name("reference")), static_cast<float>(ref.latDeg), static_cast<float>(ref.lonDeg), 0.0f, 0.0f);
  glUniform4f(u(name("referenceTrig")), static_cast<float>(std::cos(la)), static_cast<float>(std::sin(la)),
              static_cast<float>(std::cos(lo)), static_cast<float>(std::sin(lo)));
  glUniform1i(u(name("data")), b.firstUnit);
  glUniform1i(u(name("lookup")), b.firstUnit + 1);
}

void GridVolumeGL::bindSamplerTextures(const SamplerBindingGL& b, const VolumeRenderOptions&) const {
  glBindTextureUnit(static_cast<GLuint>(b.firstUnit), values_);
  glBindTextureUnit(static_cast<GLuint>(b.firstUnit + 1), lookup_);
}

}  // namespace atmoglobe::engine
