#include <atmoglobe/engine/RadarVolumeRendererGL.h>

#include <atmoglobe/globe/Ellipsoid.h>

#include <glm/gtc/packing.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>

namespace atmoglobe::engine {

namespace {

constexpr int kTransferEntries = 4096;

/// Lowest value stored in the occupancy grid for "nothing measured here".
constexpr float kCoarseEmpty = -60000.0f;

/// Beam-model position in the site's ENU frame (m) of (range, azimuth, elevation): the
/// effective-Earth height/ground distance (Doviak & Zrnic 2.28) placed on the local sphere of
/// the ellipsoid's normal-section radius in that azimuth; the forward twin of the shader's
/// inverse (metres off the exact path: far below the grid's cells, which are kilometres).
glm::dvec3 beamEnu(double rangeM, double azDeg, double elDeg, double h0, double effectiveRadius,
                   double meridional, double primeVertical) {
  const double el = elDeg * M_PI / 180.0, az = azDeg * M_PI / 180.0;
  const double re = effectiveRadius;
  const double h = std::sqrt(rangeM * rangeM + (re + h0) * (re + h0) + 2.0 * rangeM * (re + h0) * std::sin(el)) - re;
  const double s = re * std::asin(std::clamp(rangeM * std::cos(el) / (re + h), -1.0, 1.0));
  const double ca = std::cos(az), sa = std::sin(az);
  const double rAlpha = 1.0 / (ca * ca / meridional + sa * sa / primeVertical);
  const double psi = s / rAlpha, d = rAlpha + h;
  const double horizontal = d * std::sin(psi);
  return {horizontal * sa, horizontal * ca, d * std::cos(psi) - (rAlpha + h0)};
}

/// The empty-space grid: a box in the site's ENU frame holding, per cell, the largest
/// measured value that any sample inside the cell can be interpolated from. Built per block
/// of 2 rays x 4 gates of each sweep: the block's value support (its gates +-1, its rays +-1,
/// from the sweep below to the sweep above, +- half a beam at the ends) is bounded by the box
/// of 27 points on it, dilated by the support's largest bulge between them. Conservative: a cell below a threshold holds
/// no sample at or above it, so the marcher may jump across it.
struct OccupancyGrid {
  glm::ivec3 cells{1};
  glm::dvec3 minEnu{0.0}, cellSize{1.0};
  std::vector<float> values;  ///< [z][y][x]
};

OccupancyGrid occupancyGrid(const volume::PolarVolume& v, double h0, double effectiveRadius, double meridional,
                            double primeVertical) {
  const int n = static_cast<int>(v.sweeps.size());
  const double hb = 0.5 * v.beamWidthDeg;
  struct Box { glm::dvec3 lo, hi; float value; };
  std::vector<Box> boxes;
  glm::dvec3 lo(1e30), hi(-1e30);
  constexpr int kRays = 2, kGates = 4;
  for (int k = 0; k < n; ++k) {
    const auto& s = v.sweeps[k];
    const double elLo = k > 0 ? v.sweeps[k - 1].elevationDeg : s.elevationDeg - hb;
    const double elHi = k + 1 < n ? v.sweeps[k + 1].elevationDeg : s.elevationDeg + hb;
    for (int r0 = 0; r0 < s.rayCount; r0 += kRays) {
      for (int g0 = 0; g0 < s.gateCount; g0 += kGates) {
        float m = kCoarseEmpty;
        for (int ray = r0; ray < std::min(r0 + kRays, s.rayCount); ++ray) {
          for (int gate = g0; gate < std::min(g0 + kGates, s.gateCount); ++gate) {
            const float x = v.value(k, ray, gate);
            if (std::isfinite(x)) m = std::max(m, x);
          }
        }
        if (m == kCoarseEmpty) continue;
        // Support: one gate and one ray beyond the block on each side (linear interpolation).
        const double rA = std::max(0.0, s.firstGateRangeMeters + (g0 - 1.0) * s.gateSpacingMeters);
        const double rB = s.firstGateRangeMeters + (std::min(g0 + kGates, s.gateCount) + 0.5) * s.gateSpacingMeters;
        const double azA = s.azimuthDeg[(r0 + s.rayCount - 1) % s.rayCount];
        double azB = s.azimuthDeg[std::min(r0 + kRays, s.rayCount) % s.rayCount];
        if (azB <= azA) azB += 360.0;
        Box b{glm::dvec3(1e30), glm::dvec3(-1e30), m};
        for (double r : {rA, 0.5 * (rA + rB), rB}) {
          for (double az : {azA, 0.5 * (azA + azB), azB}) {
            for (double el : {elLo, 0.5 * (elLo + elHi), elHi}) {
              const glm::dvec3 p = beamEnu(r, az, el, h0, effectiveRadius, meridional, primeVertical);
              b.lo = glm::min(b.lo, p);
              b.hi = glm::max(b.hi, p);
            }
          }
        }
        // Between the sampled points the support bulges out of their box by at most the
        // sagitta of an arc of radius rB over the whole azimuth span plus that over the whole
        // elevation span (each r (1 - cos(span / 2)); the points are half a span apart, so this
        // is 4x the second-order bound), plus the beam's own curvature from the antenna to rB
        // (rB^2 / (8 Re)), plus 50 m for float rounding of the shader's cell lookup (ENU
        // positions to ~0.05 m at 500 km). KLBB: 40-600 m, against cells of 3.6 km x 300 m.
        const double azSpanRad = (azB - azA) * M_PI / 180.0, elSpanRad = (elHi - elLo) * M_PI / 180.0;
        const double bulge = rB * (2.0 - std::cos(0.5 * azSpanRad) - std::cos(0.5 * elSpanRad)) +
                             rB * rB / (8.0 * effectiveRadius) + 50.0;
        b.lo -= glm::dvec3(bulge);
        b.hi += glm::dvec3(bulge);
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
        boxes.push_back(b);
      }
    }
  }
  OccupancyGrid grid;
  if (boxes.empty()) {
    grid.values.assign(1, kCoarseEmpty);
    return grid;
  }
  // 256 x 256 x 32 cells (4 MB of R16F; KLBB: 3.6 x 3.6 km x ~600 m): the fastest of
  // 64..384 x 64..384 x 32..128 in `atmoglobe bench` (llvmpipe, docs/bench-volume.md; with the
  // second grid level 32 layers beat 48 and 64 by 3-6 %).
  grid.cells = glm::ivec3(256, 256, 32);
  grid.cellSize = (hi - lo) / glm::dvec3(grid.cells - 2) + 1e-3;  // one spare cell on each side
  grid.minEnu = lo - grid.cellSize;
  grid.values.assign(static_cast<std::size_t>(grid.cells.x) * grid.cells.y * grid.cells.z, kCoarseEmpty);
  for (const Box& b : boxes) {
    // Every cell the (bulge-dilated) box touches.
    const glm::ivec3 c0 = glm::max(glm::ivec3(glm::floor((b.lo - grid.minEnu) / grid.cellSize)), glm::ivec3(0));
    const glm::ivec3 c1 = glm::min(glm::ivec3(glm::floor((b.hi - grid.minEnu) / grid.cellSize)), grid.cells - 1);
    for (int z = c0.z; z <= c1.z; ++z) {
      for (int y = c0.y; y <= c1.y; ++y) {
        for (int x = c0.x; x <= c1.x; ++x) {
          float& cell = grid.values[(static_cast<std::size_t>(z) * grid.cells.y + y) * grid.cells.x + x];
          cell = std::max(cell, b.value);
        }
      }
    }
  }
  return grid;
}

GLuint makeTexture(GLenum target, GLint filter = GL_NEAREST) {
  GLuint t = 0;
  glCreateTextures(target, 1, &t);
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, filter);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, filter);
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

}  // namespace

volume::RenderCamera referenceCameraFor(const Camera& camera) {
  volume::RenderCamera c;
  c.eyeEcef = camera.eyeEcef();
  c.cameraToEcef = camera.cameraToEcef();
  c.focalLengthPx = camera.focalLengthPx();
  c.widthPx = camera.widthPx();
  c.heightPx = camera.heightPx();
  return c;
}

Result<std::unique_ptr<RadarVolumeGL>> RadarVolumeGL::create(const volume::PolarVolume& v) {
  const int n = static_cast<int>(v.sweeps.size());
  if (n < 1 || n > kMaxSweeps) {
    return makeError(v.sourcePath + ": " + std::to_string(n) + " sweeps; the renderer takes 1.." +
                     std::to_string(kMaxSweeps));
  }
  GLint maxSize = 0, maxLayers = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  if (v.maxGates + 1 > maxSize || v.maxRays + 1 > maxSize || kRayTableBins + 1 > maxSize || n > maxLayers) {
    return makeError(v.sourcePath + ": " + std::to_string(v.maxGates) + " gates x " + std::to_string(v.maxRays) +
                     " rays exceed the GPU's texture size " + std::to_string(maxSize));
  }
  std::unique_ptr<RadarVolumeGL> gl(new RadarVolumeGL());
  gl->polar_ = std::make_shared<volume::PolarVolume>(v);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);

  // Values: one layer per sweep, native (ray, gate) layout, RG16F = (value if echo else 0,
  // 1 if echo else 0). Bilinear filtering of these two channels gives exactly the rule's
  // weighted sum of echo values and its echo weight (PolarVolume.h, step 3) in one fetch
  // instead of four, with the rule's clamping and azimuth wrap made by padding: column
  // gateCount repeats the last gate and row rayCount repeats ray 0. No data and no echo are
  // both (0, 0): they contribute nothing in every mode, so the image does not depend on the
  // distinction (the CPU volume keeps it: `gates`, `info`, the reference renderer).
  {
    const int w = v.maxGates + 1, h = v.maxRays + 1;
    gl->values_ = makeTexture(GL_TEXTURE_2D_ARRAY, GL_LINEAR);
    glTextureStorage3D(gl->values_, 1, GL_RG16F, w, h, n);
    // Converted to half floats here and uploaded a layer at a time: the staging buffer is one
    // layer (KLBB: 5.3 MB), not the whole volume as float pairs.
    std::vector<std::uint32_t> layer(static_cast<std::size_t>(w) * h);
    for (int k = 0; k < n; ++k) {
      const auto& s = v.sweeps[k];
      std::fill(layer.begin(), layer.end(), 0u);  // (0, 0): no echo / no data / padding
      for (int row = 0; row <= s.rayCount; ++row) {
        const int ray = row % s.rayCount;
        for (int col = 0; col <= s.gateCount; ++col) {
          const float value = v.value(k, ray, std::min(col, s.gateCount - 1));
          if (volume::isMeasuredValue(value))
            layer[static_cast<std::size_t>(row) * w + col] = glm::packHalf2x16(glm::vec2(value, 1.0f));
        }
      }
      glTextureSubImage3D(gl->values_, 0, 0, 0, k, w, h, 1, GL_RG, GL_HALF_FLOAT, layer.data());
    }
    gl->valuesSize_ = glm::vec2(static_cast<float>(w), static_cast<float>(h));
    gl->gpuBytes_ += layer.size() * 4 * static_cast<std::size_t>(n);  // two half floats per texel
  }

  // Azimuth -> ray coordinate per sweep (volume::rayCoordinateTable), linearly filtered.
  {
    std::vector<float> table;
    table.reserve(static_cast<std::size_t>(kRayTableBins + 1) * n);
    for (int k = 0; k < n; ++k) {
      const std::vector<float> row = volume::rayCoordinateTable(v.sweeps[k], kRayTableBins);
      table.insert(table.end(), row.begin(), row.end());
    }
    gl->rayTable_ = makeTexture(GL_TEXTURE_1D_ARRAY, GL_LINEAR);
    glTextureStorage2D(gl->rayTable_, 1, GL_R32F, kRayTableBins + 1, n);
    glTextureSubImage2D(gl->rayTable_, 0, 0, 0, kRayTableBins + 1, n, GL_RED, GL_FLOAT, table.data());
    gl->gpuBytes_ += table.size() * 4;
  }
  // Elevation -> last sweep at or below, over the shell's elevations.
  {
    const double hb = 0.5 * v.beamWidthDeg;
    gl->elLookupRange_ = glm::vec2(static_cast<float>(v.sweeps.front().elevationDeg - hb),
                                   static_cast<float>(v.sweeps.back().elevationDeg + hb));
    std::vector<std::int32_t> el(kElevationBins, -1);
    int last = -1;
    for (int b = 0; b < kElevationBins; ++b) {
      // The bin start as the shader computes it (float), so the table never points above.
      const float start = gl->elLookupRange_.x + (gl->elLookupRange_.y - gl->elLookupRange_.x) * static_cast<float>(b) /
                                                     static_cast<float>(kElevationBins);
      while (last + 1 < n && static_cast<float>(v.sweeps[last + 1].elevationDeg) <= start) ++last;
      el[b] = last;
    }
    gl->elLookup_ = makeTexture(GL_TEXTURE_2D);
    glTextureStorage2D(gl->elLookup_, 1, GL_R32I, kElevationBins, 1);
    glTextureSubImage2D(gl->elLookup_, 0, 0, 0, kElevationBins, 1, GL_RED_INTEGER, GL_INT, el.data());
    gl->gpuBytes_ += el.size() * 4;
  }

  // Empty-space grid in the site's ENU frame.
  {
    const double latRad = v.site.latDeg * M_PI / 180.0;
    const double e2 = globe::kWgs84F * (2.0 - globe::kWgs84F);
    const double w2 = 1.0 - e2 * std::sin(latRad) * std::sin(latRad);
    const double radius = v.beam.earthRadiusMeters.value_or(globe::geocentricRadiusMeters(v.site.latDeg));
    const OccupancyGrid grid = occupancyGrid(v, v.site.antennaHeightEllipsoidMeters, v.beam.ke * radius,
                                             globe::kWgs84A * (1.0 - e2) / (w2 * std::sqrt(w2)),
                                             globe::kWgs84A / std::sqrt(w2));
    gl->gridMinEnu_ = glm::vec3(grid.minEnu);
    gl->gridCellSize_ = glm::vec3(grid.cellSize);
    gl->gridCells_ = grid.cells;
    gl->coarse_ = makeTexture(GL_TEXTURE_3D);
    glTextureStorage3D(gl->coarse_, 1, GL_R16F, grid.cells.x, grid.cells.y, grid.cells.z);
    glTextureSubImage3D(gl->coarse_, 0, 0, 0, 0, grid.cells.x, grid.cells.y, grid.cells.z, GL_RED, GL_FLOAT,
                        grid.values.data());
    gl->gpuBytes_ += grid.values.size() * 2;
    // Its second level: the max over blocks of kGridBlock^3 cells, so that a ray crosses a large
    // empty region in a few jumps instead of one per cell.
    const glm::ivec3 blocks = (grid.cells + (kGridBlock - 1)) / kGridBlock;
    std::vector<float> coarse(static_cast<std::size_t>(blocks.x) * blocks.y * blocks.z, kCoarseEmpty);
    for (int z = 0; z < grid.cells.z; ++z) {
      for (int y = 0; y < grid.cells.y; ++y) {
        for (int x = 0; x < grid.cells.x; ++x) {
          float& b = coarse[(static_cast<std::size_t>(z / kGridBlock) * blocks.y + y / kGridBlock) * blocks.x + x / kGridBlock];
          b = std::max(b, grid.values[(static_cast<std::size_t>(z) * grid.cells.y + y) * grid.cells.x + x]);
        }
      }
    }
    gl->blocks_ = makeTexture(GL_TEXTURE_3D);
    glTextureStorage3D(gl->blocks_, 1, GL_R16F, blocks.x, blocks.y, blocks.z);
    glTextureSubImage3D(gl->blocks_, 0, 0, 0, 0, blocks.x, blocks.y, blocks.z, GL_RED, GL_FLOAT, coarse.data());
    gl->gpuBytes_ += coarse.size() * 2;
  }
  return gl;
}

RadarVolumeGL::~RadarVolumeGL() {
  for (GLuint t : {values_, rayTable_, coarse_, blocks_, elLookup_}) {
    if (t) glDeleteTextures(1, &t);
  }
}

Result<std::unique_ptr<RadarVolumeRendererGL>> RadarVolumeRendererGL::create() {
  auto composite = ShaderProgramGL::create("fullscreen.vert", "composite.frag");
  if (!composite) return makeError(composite.error());
  std::unique_ptr<RadarVolumeRendererGL> r(new RadarVolumeRendererGL());
  r->composite_ = std::move(*composite);
  // The default variant now, so that a broken shader is an error here, not a missing volume.
  if (!r->marchProgram(0, 1, 0, 1)) return makeError("radar_march.frag: " + r->marchErrors_.begin()->second);
  glCreateVertexArrays(1, &r->vao_);
  glCreateSamplers(1, &r->nearestSampler_);
  for (GLenum filter : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER}) glSamplerParameteri(r->nearestSampler_, filter, GL_NEAREST);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T}) glSamplerParameteri(r->nearestSampler_, wrap, GL_CLAMP_TO_EDGE);
  r->transfer_ = makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(r->transfer_, 1, GL_RGBA32F, kTransferEntries, 1);
  r->transferIntegral_ = makeTexture(GL_TEXTURE_2D, GL_LINEAR);
  glTextureStorage2D(r->transferIntegral_, 1, GL_RGBA32F, kTransferEntries + 1, 1);
  // A 1x1 "nothing drawn" depth (0 = infinitely far in reverse-Z) for volume-only renders.
  r->emptyDepth_ = makeTexture(GL_TEXTURE_2D);
  glTextureStorage2D(r->emptyDepth_, 1, GL_R32F, 1, 1);
  const float zero = 0.0f;
  glTextureSubImage2D(r->emptyDepth_, 0, 0, 0, 1, 1, GL_RED, GL_FLOAT, &zero);
  return r;
}

RadarVolumeRendererGL::~RadarVolumeRendererGL() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (transfer_) glDeleteTextures(1, &transfer_);
  if (transferIntegral_) glDeleteTextures(1, &transferIntegral_);
  if (emptyDepth_) glDeleteTextures(1, &emptyDepth_);
  if (nearestSampler_) glDeleteSamplers(1, &nearestSampler_);
}

const ShaderProgramGL* RadarVolumeRendererGL::marchProgram(int mode, int interpolation, int beam, int skipEmpty,
                                                          int preintegrated) {
  const int key = (((mode * 2 + interpolation) * 2 + beam) * 2 + skipEmpty) * 2 + preintegrated;
  if (auto it = marchPrograms_.find(key); it != marchPrograms_.end()) return &it->second;
  if (marchErrors_.count(key)) return nullptr;
  auto program = ShaderProgramGL::create(
      "fullscreen.vert", "radar_march.frag",
      {"MARCH_MODE " + std::to_string(mode), "MARCH_INTERPOLATION " + std::to_string(interpolation),
       "MARCH_BEAM " + std::to_string(beam), "MARCH_SKIP_EMPTY " + std::to_string(skipEmpty),
       "MARCH_PREINTEGRATED " + std::to_string(preintegrated)});
  if (!program) {
    marchErrors_[key] = program.error();
    std::fprintf(stderr, "radar_march.frag variant (mode %d, interpolation %d, beam %d, skip %d, preintegrated %d): %s\n",
                 mode, interpolation, beam, skipEmpty, preintegrated, program.error().c_str());
    return nullptr;
  }
  return &marchPrograms_.emplace(key, std::move(*program)).first->second;
}

void RadarVolumeRendererGL::ensureTarget(int widthPx, int heightPx, GLenum format) {
  if (volumeTarget_ && volumeTarget_->widthPx() == widthPx && volumeTarget_->heightPx() == heightPx &&
      volumeFormat_ == format) {
    return;
  }
  auto t = FramebufferGL::create(widthPx, heightPx, format);
  assert(t);
  volumeTarget_ = std::move(*t);
  volumeFormat_ = format;
}

bool RadarVolumeRendererGL::setUniforms(const Camera& camera, const RadarVolumeGL& gl,
                                        const RadarRenderOptions& options, GLuint depthTexture, bool debugMode) {
  const volume::PolarVolume& v = gl.polar();
  const volume::VolumeRenderSettings& rs = options.render;
  const int mode = rs.mode == volume::VolumeRenderMode::Dvr ? 0 : rs.mode == volume::VolumeRenderMode::Mip ? 1 : 2;
  const bool preintegrated = !debugMode && mode == 0 && options.classification == Classification::Preintegrated;
  march_ = marchProgram(debugMode ? 3 : mode, rs.interpolation == volume::Interpolation::Nearest ? 0 : 1,
                        options.beam == BeamApproximation::StraightLine ? 1 : 0, options.skipEmptySpace ? 1 : 0,
                        preintegrated ? 1 : 0);
  if (!march_) return false;
  const GLuint p = march_->id();
  march_->use();
  const int n = static_cast<int>(v.sweeps.size());
  std::vector<glm::vec4> geom(n);
  std::vector<GLint> rays(n);
  for (int k = 0; k < n; ++k) {
    const auto& s = v.sweeps[k];
    // Narrowed to float: angles (1e-7 deg), ranges (< 1 mm at 1000 km).
    geom[k] = glm::vec4(static_cast<float>(s.elevationDeg), static_cast<float>(s.firstGateRangeMeters),
                        static_cast<float>(s.gateSpacingMeters), static_cast<float>(s.gateCount));
    rays[k] = s.rayCount;
  }
  glUniform4fv(glGetUniformLocation(p, "u_sweepGeom"), n, glm::value_ptr(geom[0]));
  glUniform1iv(glGetUniformLocation(p, "u_sweepRays"), n, rays.data());
  glUniform1i(glGetUniformLocation(p, "u_sweepCount"), n);
  const double halfBeam = 0.5 * v.beamWidthDeg;
  glUniform1f(glGetUniformLocation(p, "u_halfBeamDeg"), static_cast<float>(halfBeam));
  // Clip sphere: holds every point within maxRange along the bent beams (PolarVolume.h).
  const double clipRadius = v.clipRadiusMeters > 0.0 ? v.clipRadiusMeters : v.maxRangeMeters;
  glUniform1f(glGetUniformLocation(p, "u_maxRange"), static_cast<float>(clipRadius));

  // Earth model at the site.
  const double latRad = v.site.latDeg * M_PI / 180.0;
  const double e2 = globe::kWgs84F * (2.0 - globe::kWgs84F);
  const double w2 = 1.0 - e2 * std::sin(latRad) * std::sin(latRad);
  const double primeVertical = globe::kWgs84A / std::sqrt(w2);
  const double meridional = globe::kWgs84A * (1.0 - e2) / (w2 * std::sqrt(w2));
  const double radius = v.beam.earthRadiusMeters.value_or(globe::geocentricRadiusMeters(v.site.latDeg));
  const double effective = v.beam.ke * radius;
  // Straight-line elevation band holding every beam: a beam bends by at most
  // r / (2R) * |1 - 1/ke| radians against a straight line out to r (plus 0.05 deg slack).
  const bool straight = options.beam == BeamApproximation::StraightLine;
  const double bendDeg = straight ? 0.0 : clipRadius / (2.0 * radius) * std::abs(1.0 - 1.0 / v.beam.ke) * 180.0 / M_PI;
  const double lo = v.sweeps.front().elevationDeg - halfBeam - bendDeg - 0.05;
  const double hi = v.sweeps.back().elevationDeg + halfBeam + bendDeg + 0.05;
  glUniform2f(glGetUniformLocation(p, "u_straightElevationClipSin"), static_cast<float>(std::sin(std::max(lo, -90.0) * M_PI / 180.0)),
              static_cast<float>(std::sin(std::min(hi, 90.0) * M_PI / 180.0)));
  glUniform3fv(glGetUniformLocation(p, "u_gridMinEnu"), 1, glm::value_ptr(gl.gridMinEnu_));
  glUniform3fv(glGetUniformLocation(p, "u_gridCellSize"), 1, glm::value_ptr(gl.gridCellSize_));
  glUniform3iv(glGetUniformLocation(p, "u_gridCells"), 1, glm::value_ptr(gl.gridCells_));
  const glm::dmat3 enu = globe::enuAxes(v.site.latDeg, v.site.lonDeg);
  const glm::mat3 ecefToEnu = glm::mat3(glm::transpose(enu));
  glUniformMatrix3fv(glGetUniformLocation(p, "u_ecefToEnu"), 1, GL_FALSE, glm::value_ptr(ecefToEnu));
  glUniform1f(glGetUniformLocation(p, "u_h0"), static_cast<float>(v.site.antennaHeightEllipsoidMeters));
  glUniform1f(glGetUniformLocation(p, "u_meridionalRadius"), static_cast<float>(meridional));
  glUniform1f(glGetUniformLocation(p, "u_primeVerticalRadius"), static_cast<float>(primeVertical));
  glUniform1f(glGetUniformLocation(p, "u_effectiveRadius"), static_cast<float>(effective));

  // Camera relative to the antenna: subtracted in double, then narrowed.
  const glm::dvec3 site = globe::geodeticToEcef({v.site.latDeg, v.site.lonDeg, v.site.antennaHeightEllipsoidMeters});
  const glm::vec3 eyeRelSite = glm::vec3(camera.eyeEcef() - site);
  glUniform3fv(glGetUniformLocation(p, "u_eyeRelSite"), 1, glm::value_ptr(eyeRelSite));
  const glm::mat3 cameraToEcef = glm::mat3(camera.cameraToEcef());
  glUniformMatrix3fv(glGetUniformLocation(p, "u_cameraToEcef"), 1, GL_FALSE, glm::value_ptr(cameraToEcef));
  glUniform1f(glGetUniformLocation(p, "u_focalPx"), static_cast<float>(camera.focalLengthPx()));
  glUniform2f(glGetUniformLocation(p, "u_imageSizePx"), static_cast<float>(camera.widthPx()),
              static_cast<float>(camera.heightPx()));
  glUniform1f(glGetUniformLocation(p, "u_near"), static_cast<float>(camera.nearMeters()));

  glUniform1f(glGetUniformLocation(p, "u_step"), static_cast<float>(rs.stepMeters));
  glUniform1f(glGetUniformLocation(p, "u_isoValue"), static_cast<float>(rs.isoValue));
  glUniform1f(glGetUniformLocation(p, "u_earlyTermination"), static_cast<float>(rs.earlyTerminationAlpha));
  // MIP: a maximum below the colour table's first stop is transparent, so blocks below it
  // can be skipped too.
  const auto& stops = rs.transfer.colors.stops();
  const double firstVisible = stops.empty() ? -1e30 : (stops.front().value - rs.transfer.colors.offset()) / rs.transfer.colors.scale();
  glUniform1f(glGetUniformLocation(p, "u_mipVisibleMin"), static_cast<float>(firstVisible));
  glUniform1f(glGetUniformLocation(p, "u_opacityZeroValue"), static_cast<float>(rs.transfer.opacityZeroValue));

  // Transfer function tabulated over the volume's value range (4096 entries; the value is
  // quantised to (max - min) / 4096, ~0.03 dBZ for reflectivity).
  const double tfLo = std::min<double>(v.minValue, rs.isoValue) - 1.0;
  const double tfHi = std::max<double>(v.maxValue, rs.isoValue) + 1.0;
  // For DVR the opacity is already corrected for the step (1 - (1 - alpha)^(step / reference),
  // in double here instead of a pow per sample on the GPU); pre-integrated DVR takes the
  // extinction per metre instead (the shader needs paths of a step and of half a step) and the
  // cumulative integrals; MIP and iso use the table's alpha.
  std::vector<glm::vec4> table(kTransferEntries);
  for (int i = 0; i < kTransferEntries; ++i) {
    const double value = tfLo + (i + 0.5) / kTransferEntries * (tfHi - tfLo);
    glm::dvec4 c = rs.transfer.classify(value);
    if (preintegrated) {
      c.a = rs.transfer.extinctionPerMeter(c.a);
    } else if (mode == 0) {
      c.a = rs.transfer.correctedOpacity(c.a, rs.stepMeters);
    }
    table[i] = glm::vec4(c);
  }
  glTextureSubImage2D(transfer_, 0, 0, 0, kTransferEntries, 1, GL_RGBA, GL_FLOAT, table.data());
  if (preintegrated) {
    const std::vector<glm::dvec4> integral = volume::transferIntegralTable(rs.transfer, tfLo, tfHi, kTransferEntries);
    const std::vector<glm::vec4> narrowed(integral.begin(), integral.end());
    glTextureSubImage2D(transferIntegral_, 0, 0, 0, kTransferEntries + 1, 1, GL_RGBA, GL_FLOAT, narrowed.data());
  }
  glUniform2f(glGetUniformLocation(p, "u_tfRange"), static_cast<float>(tfLo), static_cast<float>(tfHi));

  glUniform2fv(glGetUniformLocation(p, "u_elLookupRange"), 1, glm::value_ptr(gl.elLookupRange_));
  glUniform2f(glGetUniformLocation(p, "u_valuesInvSize"), 1.0f / gl.valuesSize_.x, 1.0f / gl.valuesSize_.y);
  const GLuint textures[] = {gl.values_,   gl.rayTable_, gl.coarse_, transfer_, depthTexture, gl.elLookup_, gl.blocks_,
                             transferIntegral_};
  const char* names[] = {"u_values",   "u_rayTable",   "u_grid",       "u_transfer",
                         "u_globeDepth", "u_elLookup", "u_gridBlocks", "u_tfIntegral"};
  for (int i = 0; i < 8; ++i) {
    glBindTextureUnit(static_cast<GLuint>(i), textures[i]);
    glUniform1i(glGetUniformLocation(p, names[i]), i);
  }
  // Nearest: the same fetch through a nearest-filtering sampler picks texel (round(a), round(g)),
  // the rule's nearest texel (the padding row and column give the wrap and the clamp).
  glBindSampler(0, rs.interpolation == volume::Interpolation::Nearest ? nearestSampler_ : 0);
  return true;
}

void RadarVolumeRendererGL::draw(const Camera& camera, const RadarVolumeGL& volume, const RadarRenderOptions& options,
                                 const FramebufferGL& target) {
  const double scale = std::clamp(options.imageScale, 0.05, 1.0);
  const int w = std::max(1, static_cast<int>(std::lround(target.widthPx() * scale)));
  const int h = std::max(1, static_cast<int>(std::lround(target.heightPx() * scale)));
  ensureTarget(w, h, GL_RGBA16F);
  volumeTarget_->bind();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  if (!setUniforms(camera, volume, options, target.depthTexture())) {
    // The variant failed to compile (reported on stderr): leave the target as it was.
    target.bind();
    glEnable(GL_DEPTH_TEST);
    return;
  }
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindSampler(0, 0);

  target.bind();
  composite_.use();
  glBindTextureUnit(0, volumeTarget_->colorTexture());
  glUniform1i(composite_.uniform("u_volume"), 0);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glBindVertexArray(0);
}

std::vector<glm::vec4> RadarVolumeRendererGL::readVolumeImage() const {
  std::vector<glm::vec4> out;
  if (!volumeTarget_) return out;
  const int w = volumeTarget_->widthPx(), h = volumeTarget_->heightPx();
  std::vector<glm::vec4> raw(static_cast<std::size_t>(w) * h);
  glGetTextureImage(volumeTarget_->colorTexture(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(raw.size() * sizeof(glm::vec4)),
                    raw.data());
  out.resize(raw.size());
  for (int y = 0; y < h; ++y) {
    std::copy_n(raw.begin() + static_cast<std::ptrdiff_t>(h - 1 - y) * w, w, out.begin() + static_cast<std::ptrdiff_t>(y) * w);
  }
  return out;
}

std::vector<glm::vec4> RadarVolumeRendererGL::antennaCoordinatesAt(const Camera& camera, const RadarVolumeGL& volume,
                                                                   BeamApproximation beam, double tMeters) {
  ensureTarget(camera.widthPx(), camera.heightPx(), GL_RGBA32F);
  volumeTarget_->bind();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  RadarRenderOptions options;
  options.beam = beam;
  if (!setUniforms(camera, volume, options, emptyDepth_, true)) {
    glEnable(GL_DEPTH_TEST);
    return {};
  }
  glUniform1f(march_->uniform("u_debugT"), static_cast<float>(tMeters));
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindSampler(0, 0);
  glBindVertexArray(0);
  glEnable(GL_DEPTH_TEST);
  return readVolumeImage();
}

}  // namespace atmoglobe::engine
