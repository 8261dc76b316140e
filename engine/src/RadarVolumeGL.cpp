#include <atmoglobe/engine/RadarVolumeGL.h>

#include "LoaderGL.h"

#include <atmoglobe/globe/Angles.h>

#include <atmoglobe/volume/Decimate.h>
#include <atmoglobe/volume/StepCache.h>

#include <glm/gtc/packing.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>

namespace atmoglobe::engine {

Status RadarVolumeGL::checkDrawable(const volume::PolarVolume& v) {
  const int n = static_cast<int>(v.sweeps.size());
  if (n < 1 || n > MarchConstants::kMaxSweeps)
    return makeError(v.sourcePath + ": " + std::to_string(n) + " sweeps; the renderer takes 1.." +
                     std::to_string(MarchConstants::kMaxSweeps));
  return Ok{};
}

Result<std::unique_ptr<RadarVolumeGL>> RadarVolumeGL::create(const volume::PolarVolume& v, double exaggeration) {
  if (auto st = checkDrawable(v); !st) return st.forwardError();
  return create(prepare(v, exaggeration));
}

Result<std::unique_ptr<RadarVolumeGL>> RadarVolumeGL::create(std::shared_ptr<const Prepared> pr) {
  using C = MarchConstants;
  const volume::PolarVolume& v = *pr->polar;
  const int n = static_cast<int>(v.sweeps.size());
  GLint maxSize = 0, maxLayers = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  if (C::kRayTableBins + 1 > maxSize || n + 1 > maxLayers)
    return makeError(v.sourcePath + ": " + std::to_string(n) + " sweeps: the GPU's texture limits (size " +
                     std::to_string(maxSize) + ", layers " + std::to_string(maxLayers) + ") are too small");
  // A volume the GPU cannot hold (texture size, GL_OUT_OF_MEMORY, or the artificial limit
  // $ATMOGLOBE_MAX_TEXTURE_BYTES) is drawn with every 2nd gate (and ray, where rays exceed the
  // texture size), and so on, with a warning.
  for (int halvings = 0;; ++halvings) {
    const volume::PolarVolume& p = *pr->polar;
    std::string tooLarge;
    const std::string shape = std::to_string(p.maxGates) + " gates x " + std::to_string(p.maxRays) + " rays x " +
                              std::to_string(n) + " sweeps";
    const std::size_t bytes = static_cast<std::size_t>(p.maxGates + 1) * (p.maxRays + 1) * n * 4;
    if (p.maxGates + 1 > maxSize || p.maxRays + 1 > maxSize) {
      tooLarge = shape + " exceed the GPU's texture size " + std::to_string(maxSize);
    } else if (const std::size_t limit = textureByteLimit(); limit > 0 && bytes > limit) {
      tooLarge = shape + " need a " + megabytes(bytes) + " texture, over the GPU memory limit " + megabytes(limit) +
                 " ($ATMOGLOBE_MAX_TEXTURE_BYTES)";
    } else {
      auto gl = upload(pr);
      if (gl) return gl;
      tooLarge = shape + ": the GPU is out of memory (GL_OUT_OF_MEMORY) for its " + megabytes(bytes) + " texture";
    }
    if (halvings == kMaxHalvings || p.maxGates < 8)
      return makeError(v.sourcePath + ": " + tooLarge + ", even at 1/" + std::to_string(1 << halvings) +
                       " of the resolution");
    volume::PolarVolume reduced = volume::decimatePolar(p, 2, p.maxRays + 1 > maxSize);
    std::cerr << "atmoglobe: warning: " << v.sourcePath << ": " << tooLarge << "; drawn at lower resolution, "
              << reduced.maxGates << " gates x " << reduced.maxRays << " rays (every 2nd gate"
              << (reduced.maxRays < p.maxRays ? " and ray" : "") << ")\n";
    pr = prepare(reduced, pr->exaggeration);
  }
}

std::uint64_t RadarVolumeGL::Prepared::bytes() const {
  return volume::polarVolumeBytes(*polar) + layers.capacity() * sizeof(std::uint32_t) +
         table.capacity() * sizeof(float) +
         (occupancy.maxValues.capacity() + occupancy.blockMaxValues.capacity()) * sizeof(float);
}

std::shared_ptr<const RadarVolumeGL::Prepared> RadarVolumeGL::prepare(const volume::PolarVolume& volume,
                                                                      double exaggeration) {
  using C = MarchConstants;
  auto pr = std::make_shared<Prepared>();
  pr->polar = std::make_shared<const volume::PolarVolume>(volume);
  const volume::PolarVolume& v = *pr->polar;
  const int n = static_cast<int>(v.sweeps.size());
  pr->sampler = std::make_shared<const volume::PolarSampler>(v);
  pr->exaggeration = exaggeration;
  if (exaggeration != 1.0)
    pr->exaggerated = std::make_shared<const volume::ExaggeratedSampler>(*pr->sampler, exaggeration);
  pr->beamModel = volume::localSphereBeam(v.site, v.beam);

  // Values: one layer per sweep, native (ray, gate) layout, RG16F = (value if echo else 0,
  // 1 if echo else 0). Bilinear filtering of these two channels gives exactly the rule's
  // weighted sum of echo values and its echo weight (PolarVolume.h, step 3) in one fetch
  // instead of four, with the rule's clamping and azimuth wrap made by padding: column
  // gateCount repeats the last gate and row rayCount repeats ray 0. No data and no echo are
  // both (0, 0): they contribute nothing in every mode, so the image does not depend on the
  // distinction (the CPU volume keeps it: `gates`, `info`, the reference renderer).
  // Converted to half floats here (the whole volume at 4 bytes a texel, what the GPU holds), so
  // a worker thread can do it and the GL thread only uploads.
  const int w = v.maxGates + 1, h = v.maxRays + 1;
  pr->valuesSize = glm::ivec2(w, h);
  pr->layers.assign(static_cast<std::size_t>(w) * h * static_cast<std::size_t>(n), 0u);  // (0, 0): no echo / no data
  for (int k = 0; k < n; ++k) {
    const auto& s = v.sweeps[k];
    std::uint32_t* layer = pr->layers.data() + static_cast<std::size_t>(k) * w * h;
    for (int row = 0; row <= s.rayCount; ++row) {
      const int ray = row % s.rayCount;
      for (int col = 0; col <= s.gateCount; ++col) {
        const float value = v.value(k, ray, std::min(col, s.gateCount - 1));
        if (volume::isMeasuredValue(value))
          layer[static_cast<std::size_t>(row) * w + col] = glm::packHalf2x16(glm::vec2(value, 1.0f));
      }
    }
  }

  // Azimuth -> ray coordinate per sweep (volume::rayCoordinateTable), linearly filtered; then one
  // more layer: elevation -> last sweep at or below, over the shell's elevations (fetched by
  // texel, so the filter does not apply; sweep indices are exact in float).
  {
    const int bins = C::kRayTableBins + 1;
    std::vector<float>& table = pr->table;
    table.reserve(static_cast<std::size_t>(bins) * (n + 1));
    for (int k = 0; k < n; ++k) {
      const std::vector<float> row = volume::rayCoordinateTable(v.sweeps[k], C::kRayTableBins);
      table.insert(table.end(), row.begin(), row.end());
    }
    const double hb = 0.5 * v.beamWidthDeg;
    pr->elLookupRange = glm::vec2(static_cast<float>(v.sweeps.front().elevationDeg - hb),
                                  static_cast<float>(v.sweeps.back().elevationDeg + hb));
    std::vector<float> el(static_cast<std::size_t>(bins), -1.0f);
    int last = -1;
    for (int b = 0; b < C::kElevationBins; ++b) {
      // The bin start as the shader computes it (float), so the table never points above.
      const float start = pr->elLookupRange.x + (pr->elLookupRange.y - pr->elLookupRange.x) * static_cast<float>(b) /
                                                    static_cast<float>(C::kElevationBins);
      while (last + 1 < n && static_cast<float>(v.sweeps[last + 1].elevationDeg) <= start) ++last;
      el[static_cast<std::size_t>(b)] = static_cast<float>(last);
    }
    table.insert(table.end(), el.begin(), el.end());
  }
  pr->occupancy = volume::buildOccupancyGrid(v, exaggeration);
  return pr;
}

std::unique_ptr<RadarVolumeGL> RadarVolumeGL::upload(const std::shared_ptr<const Prepared>& pr) {
  using C = MarchConstants;
  const int n = static_cast<int>(pr->polar->sweeps.size());
  std::unique_ptr<RadarVolumeGL> gl(new RadarVolumeGL());
  gl->polar_ = pr->polar;
  gl->sampler_ = pr->sampler;
  gl->exaggeration_ = pr->exaggeration;
  gl->exaggerated_ = pr->exaggerated;
  gl->beamModel_ = pr->beamModel;
  gl->elLookupRange_ = pr->elLookupRange;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  const int w = pr->valuesSize.x, h = pr->valuesSize.y;
  gl->values_ = makeVolumeTextureGL(GL_TEXTURE_2D_ARRAY, GL_LINEAR);
  clearErrorsGL();
  glTextureStorage3D(gl->values_, 1, GL_RG16F, w, h, n);
  if (outOfMemoryGL()) return nullptr;  // ~RadarVolumeGL deletes the texture
  glTextureSubImage3D(gl->values_, 0, 0, 0, 0, w, h, n, GL_RG, GL_HALF_FLOAT, pr->layers.data());
  gl->valuesSize_ = glm::vec2(static_cast<float>(w), static_cast<float>(h));
  gl->gpuBytes_ += pr->layers.size() * 4;  // two half floats per texel
  const int bins = C::kRayTableBins + 1;
  gl->rayTable_ = makeVolumeTextureGL(GL_TEXTURE_1D_ARRAY, GL_LINEAR);
  glTextureStorage2D(gl->rayTable_, 1, GL_R32F, bins, n + 1);
  glTextureSubImage2D(gl->rayTable_, 0, 0, 0, bins, n + 1, GL_RED, GL_FLOAT, pr->table.data());
  gl->gpuBytes_ += pr->table.size() * 4;
  gl->occupancy_ = OccupancyGridGL(pr->occupancy);
  return gl;
}

RadarVolumeGL::~RadarVolumeGL() {
  for (GLuint t : {values_, rayTable_})
    if (t) glDeleteTextures(1, &t);
}

std::vector<std::string> RadarVolumeGL::samplerDefines(const VolumeRenderOptions& options) const {
  return {std::string("INTERPOLATION ") + (options.render.interpolation == volume::Interpolation::Nearest ? "0" : "1"),
          std::string("BEAM ") + (beam_ == BeamApproximation::StraightLine ? "1" : "0"),
          std::string("EXAGGERATED ") + (exaggeration_ != 1.0 ? "1" : "0")};
}

void RadarVolumeGL::setSamplerUniforms(const SamplerBindingGL& b) const {
  UniformCacheGL& u = *b.uniforms;
  const std::string& p = b.prefix;
  const volume::PolarVolume& v = *polar_;
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
  glUniform4fv(u(p + "sweepGeom"), n, glm::value_ptr(geom[0]));
  glUniform1iv(u(p + "sweepRays"), n, rays.data());
  glUniform1i(u(p + "sweepCount"), n);
  glUniform1f(u(p + "halfBeamDeg"), static_cast<float>(0.5 * v.beamWidthDeg));
  const volume::PolarCellScale cells = volume::polarCellScale(v);  // the step rule's (StepRule.h)
  glUniform2f(u(p + "cellScale"), static_cast<float>(cells.gateMeters), static_cast<float>(cells.acrossRad));
  // Clip sphere: holds every point within maxRange along the bent beams (PolarVolume.h).
  const double clipRadius = v.clipRadiusMeters > 0.0 ? v.clipRadiusMeters : v.maxRangeMeters;
  // Exaggerated: the clip sphere grows by |e - 1| times the highest point the beams reach (the
  // ray interval is then the sphere alone: the straight-elevation band does not hold bent beams
  // stretched vertically).
  double topHeight = 0.0, ground = 0.0;
  if (!v.sweeps.empty())
    volume::beamHeightAndGroundDistance(clipRadius, v.sweeps.back().elevationDeg + 0.5 * v.beamWidthDeg,
                                        beamModel_.antennaHeightMeters, beamModel_.effectiveRadiusMeters, &topHeight,
                                        &ground);
  const double grow = std::abs(exaggeration_ - 1.0) * (std::abs(topHeight) + std::abs(beamModel_.antennaHeightMeters));
  glUniform1f(u(p + "maxRange"), static_cast<float>(clipRadius + grow));
  glUniform1f(u(p + "exaggeration"), static_cast<float>(exaggeration_));
  const volume::StraightElevationBand band = volume::straightElevationBand(v, beam_ == BeamApproximation::StraightLine);
  glUniform2f(u(p + "straightElevationClipSin"),
              static_cast<float>(std::sin(degreesToRadians(band.loDegAt(clipRadius)))),
              static_cast<float>(std::sin(degreesToRadians(band.hiDegAt(clipRadius)))));
  const glm::mat3 ecefToEnu = glm::mat3(glm::transpose(beamModel_.enuToEcef));
  glUniformMatrix3fv(u(p + "ecefToEnu"), 1, GL_FALSE, glm::value_ptr(ecefToEnu));
  glUniform1f(u(p + "h0"), static_cast<float>(beamModel_.antennaHeightMeters));
  glUniform1f(u(p + "meridionalRadius"), static_cast<float>(beamModel_.meridionalRadiusMeters));
  glUniform1f(u(p + "primeVerticalRadius"), static_cast<float>(beamModel_.primeVerticalRadiusMeters));
  glUniform1f(u(p + "effectiveRadius"), static_cast<float>(beamModel_.effectiveRadiusMeters));
  glUniform2fv(u(p + "elLookupRange"), 1, glm::value_ptr(elLookupRange_));
  glUniform2f(u(p + "valuesInvSize"), 1.0f / valuesSize_.x, 1.0f / valuesSize_.y);
  glUniform1i(u(p + "values"), b.firstUnit);
  glUniform1i(u(p + "rayTable"), b.firstUnit + 1);
}

void RadarVolumeGL::bindSamplerTextures(const SamplerBindingGL& b, const VolumeRenderOptions& options) const {
  glBindTextureUnit(static_cast<GLuint>(b.firstUnit), values_);
  // Nearest: the same fetch through a nearest-filtering sampler picks texel (round(a), round(g)),
  // the rule's nearest texel (the padding row and column give the wrap and the clamp).
  glBindSampler(static_cast<GLuint>(b.firstUnit),
                options.render.interpolation == volume::Interpolation::Nearest ? b.nearestSampler : 0);
  glBindTextureUnit(static_cast<GLuint>(b.firstUnit + 1), rayTable_);
}

}  // namespace atmoglobe::engine
