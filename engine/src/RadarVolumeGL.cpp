#include <atmoglobe/engine/RadarVolumeGL.h>

#include <atmoglobe/globe/Angles.h>

#include <atmoglobe/volume/Decimate.h>

#include <glm/gtc/packing.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>

namespace atmoglobe::engine {

Result<std::unique_ptr<RadarVolumeGL>> RadarVolumeGL::create(const volume::PolarVolume& v, double exaggeration) {
  using C = MarchConstants;
  const int n = static_cast<int>(v.sweeps.size());
  if (n < 1 || n > C::kMaxSweeps) {
    return makeError(v.sourcePath + ": " + std::to_string(n) + " sweeps; the renderer takes 1.." +
                     std::to_string(C::kMaxSweeps));
  }
  GLint maxSize = 0, maxLayers = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  if (C::kRayTableBins + 1 > maxSize || n + 1 > maxLayers)
    return makeError(v.sourcePath + ": " + std::to_string(n) + " sweeps: the GPU's texture limits (size " +
                     std::to_string(maxSize) + ", layers " + std::to_string(maxLayers) + ") are too small");
  // A volume the GPU cannot hold (texture size, GL_OUT_OF_MEMORY, or the artificial limit
  // $ATMOGLOBE_MAX_TEXTURE_BYTES) is drawn with every 2nd gate (and ray, where rays exceed the
  // texture size), and so on, with a warning.
  volume::PolarVolume reduced;
  const volume::PolarVolume* p = &v;
  for (int halvings = 0;; ++halvings) {
    std::string tooLarge;
    const std::string shape = std::to_string(p->maxGates) + " gates x " + std::to_string(p->maxRays) + " rays x " +
                              std::to_string(n) + " sweeps";
    const std::size_t bytes = static_cast<std::size_t>(p->maxGates + 1) * (p->maxRays + 1) * n * 4;
    if (p->maxGates + 1 > maxSize || p->maxRays + 1 > maxSize) {
      tooLarge = shape + " exceed the GPU's texture size " + std::to_string(maxSize);
    } else if (const std::size_t limit = textureByteLimit(); limit > 0 && bytes > limit) {
      tooLarge = shape + " need a " + megabytes(bytes) + " texture, over the GPU memory limit " + megabytes(limit) +
                 " ($ATMOGLOBE_MAX_TEXTURE_BYTES)";
    } else {
      auto gl = createAt(*p, exaggeration);
      if (gl) return gl;
      tooLarge = shape + ": the GPU is out of memory (GL_OUT_OF_MEMORY) for its " + megabytes(bytes) + " texture";
    }
    if (halvings == kMaxHalvings || p->maxGates < 8)
      return makeError(v.sourcePath + ": " + tooLarge + ", even at 1/" + std::to_string(1 << halvings) +
                       " of the resolution");
    reduced = volume::decimatePolar(*p, 2, p->maxRays + 1 > maxSize);
    std::cerr << "atmoglobe: warning: " << v.sourcePath << ": " << tooLarge << "; drawn at lower resolution, "
              << reduced.maxGates << " gates x " << reduced.maxRays << " rays (every 2nd gate"
              << (reduced.maxRays < p->maxRays ? " and ray" : "") << ")\n";
    p = &reduced;
  }
}

std::unique_ptr<RadarVolumeGL> RadarVolumeGL::createAt(const volume::PolarVolume& v, double exaggeration) {
  using C = MarchConstants;
  const int n = static_cast<int>(v.sweeps.size());
  std::unique_ptr<RadarVolumeGL> gl(new RadarVolumeGL());
  gl->polar_ = std::make_shared<volume::PolarVolume>(v);
  gl->sampler_ = std::make_unique<volume::PolarSampler>(*gl->polar_);
  gl->exaggeration_ = exaggeration;
  if (exaggeration != 1.0) gl->exaggerated_ = std::make_unique<volume::ExaggeratedSampler>(*gl->sampler_, exaggeration);
  gl->beamModel_ = volume::localSphereBeam(v.site, v.beam);
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
    gl->values_ = makeVolumeTextureGL(GL_TEXTURE_2D_ARRAY, GL_LINEAR);
    clearErrorsGL();
    glTextureStorage3D(gl->values_, 1, GL_RG16F, w, h, n);
    if (outOfMemoryGL()) return nullptr;  // ~RadarVolumeGL deletes the texture
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

  // Azimuth -> ray coordinate per sweep (volume::rayCoordinateTable), linearly filtered; then one
  // more layer: elevation -> last sweep at or below, over the shell's elevations (fetched by
  // texel, so the filter does not apply; sweep indices are exact in float).
  {
    const int bins = C::kRayTableBins + 1;
    std::vector<float> table;
    table.reserve(static_cast<std::size_t>(bins) * (n + 1));
    for (int k = 0; k < n; ++k) {
      const std::vector<float> row = volume::rayCoordinateTable(v.sweeps[k], C::kRayTableBins);
      table.insert(table.end(), row.begin(), row.end());
    }
    const double hb = 0.5 * v.beamWidthDeg;
    gl->elLookupRange_ = glm::vec2(static_cast<float>(v.sweeps.front().elevationDeg - hb),
                                   static_cast<float>(v.sweeps.back().elevationDeg + hb));
    std::vector<float> el(static_cast<std::size_t>(bins), -1.0f);
    int last = -1;
    for (int b = 0; b < C::kElevationBins; ++b) {
      // The bin start as the shader computes it (float), so the table never points above.
      const float start = gl->elLookupRange_.x + (gl->elLookupRange_.y - gl->elLookupRange_.x) * static_cast<float>(b) /
                                                     static_cast<float>(C::kElevationBins);
      while (last + 1 < n && static_cast<float>(v.sweeps[last + 1].elevationDeg) <= start) ++last;
      el[static_cast<std::size_t>(b)] = static_cast<float>(last);
    }
    table.insert(table.end(), el.begin(), el.end());
    gl->rayTable_ = makeVolumeTextureGL(GL_TEXTURE_1D_ARRAY, GL_LINEAR);
    glTextureStorage2D(gl->rayTable_, 1, GL_R32F, bins, n + 1);
    glTextureSubImage2D(gl->rayTable_, 0, 0, 0, bins, n + 1, GL_RED, GL_FLOAT, table.data());
    gl->gpuBytes_ += table.size() * 4;
  }
  gl->occupancy_ = OccupancyGridGL(volume::buildOccupancyGrid(v, exaggeration));
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
