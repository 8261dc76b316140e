#include <atmoglobe/engine/VolumeRendererGL.h>

#include "LoaderGL.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace atmoglobe::engine {

namespace {

constexpr int kDepthUnit = 0, kTransferUnit = 1, kIntegralUnit = 2, kFirstVolumeUnit = 3;
// Volume k's units: its empty-space grid, then its sampler's kSamplerUnits.
constexpr int gridUnit(int k) { return kFirstVolumeUnit + k * (1 + VolumeGL::kSamplerUnits); }
constexpr int samplerFirstUnit(int k) { return gridUnit(k) + 1; }
// Adaptive refinement's small image: after every volume's units.
constexpr int kCoarseUnit = gridUnit(MarchConstants::kMaxVolumes);

std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t pos = text.find(from); pos != std::string::npos; pos = text.find(from, pos + to.size()))
    text.replace(pos, from.size(), to);
  return text;
}

// "vK_", the prefix of volume K's uniforms and functions (built by appending: GCC 12 warns
// falsely, -Wrestrict, on "v" + std::string).
std::string volumePrefix(std::size_t k) {
  std::string p(1, 'v');
  p.append(std::to_string(k));
  p.push_back('_');
  return p;
}

int modeIndex(volume::VolumeRenderMode m) {
  return m == volume::VolumeRenderMode::Dvr ? 0 : m == volume::VolumeRenderMode::Mip ? 1 : 2;
}

// The generated dispatch: vol*(int k, ...) -> vK_*(...). Loops over k run to a constant, so after
// unrolling each call site names one volume and the chain folds away.
std::string dispatchSource(int count, bool columns) {
  struct Fn {
    const char* signature;  // with {ARGS} for the argument list
    const char* returnType;
    const char* call;  // the per-volume call, VOL_ = prefix
    const char* fallback;
  };
  const Fn fns[] = {
      {"vec3 volEyeRel(int k)", "vec3", "VOL_eyeRel", "vec3(0.0)"},
      {"mat3 volEcefToLocal(int k)", "mat3", "VOL_ecefToLocal", "mat3(1.0)"},
      {"vec2 volInterval(int k, vec3 dir, float tMax)", "vec2", "VOL_interval(VOL_eyeRel, dir, tMax)",
       "vec2(1.0, 0.0)"},
      {"vec2 volGridBox(int k, vec3 oL, vec3 dL)", "vec2", "VOL_gridBoxInterval(oL, dL)", "vec2(1.0, 0.0)"},
      {"vec3 volGridMinLocal(int k)", "vec3", "VOL_gridMinLocal", "vec3(0.0)"},
      {"vec3 volGridCellSize(int k)", "vec3", "VOL_gridCellSize", "vec3(1.0)"},
      {"float volEmptyUntil(int k, vec3 oC, vec3 dC, vec3 iC, vec2 box, float ts, float threshold)", "float",
       "VOL_emptyUntil(oC, dC, iC, box, ts, threshold)", "ts"},
      {"int volSample(int k, vec3 p, out float value)", "int", "VOL_sample(p, value)", "STATE_NOT_ECHO"},
      {"float volCellCrossing(int k, vec3 p, vec3 dir)", "float", "VOL_cellCrossing(p, dir)", "0.0"},
      {"vec3 volDebug(int k, vec3 p)", "vec3", "VOL_debugCoordinates(p)", "vec3(0.0)"},
      {"vec4 volClassify(int k, float v)", "vec4", "VOL_classify(v)", "vec4(0.0)"},
      {"vec4 volTfIntegral(int k, float v)", "vec4", "VOL_tfIntegral(v)", "vec4(0.0)"},
      {"vec2 volTfRange(int k)", "vec2", "VOL_tfRange", "vec2(0.0, 1.0)"},
      {"float volIso(int k)", "float", "VOL_isoValue", "0.0"},
      {"vec3 volIsoColor(int k)", "vec3", "VOL_isoColor", "vec3(0.0)"},
      {"float volOpacityZero(int k)", "float", "VOL_opacityZeroValue", "0.0"},
      {"float volSamplesPerCell(int k)", "float", "VOL_samplesPerCell", "0.0"},
      {"float volMipVisibleMin(int k)", "float", "VOL_mipVisibleMin", "0.0"},
  };
  std::ostringstream s;
  for (const Fn& f : fns) {
    s << f.signature << " {\n";
    if (std::string(f.signature).find("out float value") != std::string::npos) s << "  value = 0.0;\n";
    // The far field's columns start at g_rayOffset from the eye (volume_march.frag, MARCH_COLUMNS).
    const std::string call = columns ? replaceAll(f.call, "VOL_eyeRel", "(VOL_eyeRel + g_rayOffset)") : f.call;
    for (int k = 0; k < count; ++k)
      s << "  if (k == " << k << ") return " << replaceAll(call, "VOL_", volumePrefix(static_cast<std::size_t>(k)))
        << ";\n";
    s << "  return " << f.fallback << ";\n}\n";
  }
  return s.str();
}

}  // namespace

void appendTransferKey(const volume::TransferFunction& tf, std::vector<double>& key) {
  key.insert(key.end(), {tf.opacityZeroValue, tf.opacityFullValue, tf.maxOpacity, tf.opacityReferenceMeters,
                         tf.colors.offset(), tf.colors.scale()});
  for (const glm::dvec2& p : tf.opacityPoints) key.insert(key.end(), {p.x, p.y});
  for (const auto& stop : tf.colors.stops()) {
    key.push_back(stop.value);
    for (const volume::Rgba8& c : {stop.start, stop.end})
      key.insert(key.end(), {double(c.r), double(c.g), double(c.b), double(c.a)});
  }
}

volume::RenderCamera referenceCameraFor(const Camera& camera) {
  volume::RenderCamera c;
  c.eyeEcef = camera.eyeEcef();
  c.cameraToEcef = camera.cameraToEcef();
  c.focalLengthPx = camera.focalLengthPx();
  c.widthPx = camera.widthPx();
  c.heightPx = camera.heightPx();
  return c;
}

Result<std::unique_ptr<VolumeRendererGL>> VolumeRendererGL::create() {
  using C = MarchConstants;
  auto composite = ShaderProgramGL::create("fullscreen.vert", "composite.frag");
  if (!composite) return composite.forwardError();
  std::unique_ptr<VolumeRendererGL> r(new VolumeRendererGL());
  r->composite_ = std::move(*composite);
  GLint units = 0;
  glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
  if (units < kCoarseUnit + 1) {
    return makeError("the GPU has " + std::to_string(units) + " fragment texture units; the volume marcher needs " +
                     std::to_string(kCoarseUnit + 1));
  }
  // The default radar variant now, so that a broken shader is an error here, not a missing volume.
  MarchVariant v;
  v.volumes.push_back({"sample_polar.glsl", {"INTERPOLATION 1", "BEAM 0", "EXAGGERATED 0"}});
  if (!r->marchProgram(v)) return makeError("volume_march.frag: " + r->programErrors_.begin()->second);
  glCreateVertexArrays(1, &r->vao_);
  glCreateSamplers(1, &r->nearestSampler_);
  for (GLenum filter : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER})
    glSamplerParameteri(r->nearestSampler_, filter, GL_NEAREST);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T})
    glSamplerParameteri(r->nearestSampler_, wrap, GL_CLAMP_TO_EDGE);
  r->transfer_ = makeVolumeTextureGL(GL_TEXTURE_2D);
  glTextureStorage2D(r->transfer_, 1, GL_RGBA32F, C::kTransferEntries, C::kMaxVolumes);
  r->transferIntegral_ = makeVolumeTextureGL(GL_TEXTURE_2D, GL_LINEAR);
  glTextureStorage2D(r->transferIntegral_, 1, GL_RGBA32F, C::kTransferEntries + 1, C::kMaxVolumes);
  r->transferRows_.assign(C::kMaxVolumes, {});
  auto farField = FarFieldGL::create();
  if (!farField) return farField.forwardError();
  r->farField_ = std::move(*farField);
  // A 1x1 "nothing drawn" depth (0 = infinitely far in reverse-Z) for volume-only renders.
  r->emptyDepth_ = makeVolumeTextureGL(GL_TEXTURE_2D);
  glTextureStorage2D(r->emptyDepth_, 1, GL_R32F, 1, 1);
  const float zero = 0.0f;
  glTextureSubImage2D(r->emptyDepth_, 0, 0, 0, 1, 1, GL_RED, GL_FLOAT, &zero);
  return r;
}

VolumeRendererGL::~VolumeRendererGL() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
  for (GLuint t : {transfer_, transferIntegral_, emptyDepth_})
    if (t) glDeleteTextures(1, &t);
  if (nearestSampler_) glDeleteSamplers(1, &nearestSampler_);
}

const ShaderProgramGL* VolumeRendererGL::marchProgram(const MarchVariant& variant) {
  if (auto it = programs_.find(variant); it != programs_.end()) return &it->second.program;
  if (programErrors_.count(variant)) return nullptr;
  auto fail = [&](const std::string& error) -> const ShaderProgramGL* {
    programErrors_[variant] = error;
    std::fprintf(stderr, "volume_march.frag variant (mode %d, %zu volumes): %s\n", variant.mode, variant.volumes.size(),
                 error.c_str());
    return nullptr;
  };
  auto main = loadShaderSource("volume_march.frag");
  auto common = loadShaderSource("volume_common.glsl");
  if (!main) return fail(main.error());
  if (!common) return fail(common.error());
  const std::string marker = "// @VOLUMES@";
  const std::size_t at = main->find(marker);
  if (at == std::string::npos || variant.volumes.empty()) return fail("volume_march.frag has no " + marker + " line");
  std::ostringstream volumes;
  // Files the samplers share ("// @NEEDS FILE" lines), once each, before the volumes.
  std::vector<std::string> needed;
  for (const auto& entry : variant.volumes) {
    const std::string& file = entry.first;
    auto sampler = loadShaderSource(file);
    if (!sampler) return fail(sampler.error());
    const std::string tag = "// @NEEDS ";
    for (std::size_t pos = sampler->find(tag); pos != std::string::npos; pos = sampler->find(tag, pos + 1)) {
      const std::size_t end = sampler->find('\n', pos);
      const std::string name =
          sampler->substr(pos + tag.size(), end == std::string::npos ? end : end - pos - tag.size());
      if (std::find(needed.begin(), needed.end(), name) != needed.end()) continue;
      auto shared = loadShaderSource(name);
      if (!shared) return fail(file + " needs " + name + ": " + shared.error());
      needed.push_back(name);
      volumes << *shared << "\n";
    }
  }
  for (std::size_t k = 0; k < variant.volumes.size(); ++k) {
    const std::string prefix = volumePrefix(static_cast<std::size_t>(k));
    auto sampler = loadShaderSource(variant.volumes[k].first);
    if (!sampler) return fail(sampler.error());
    volumes << "#define " << prefix << "INDEX " << k << "\n";
    for (const std::string& d : variant.volumes[k].second) volumes << "#define " << prefix << d << "\n";
    volumes << replaceAll(*common, "VOL_", prefix) << "\n" << replaceAll(*sampler, "VOL_", prefix) << "\n";
  }
  volumes << dispatchSource(static_cast<int>(variant.volumes.size()), variant.columns);
  std::string source = main->substr(0, at) + volumes.str() + main->substr(at + marker.size());
  std::vector<std::string> defines = marchShaderDefines();
  defines.push_back("MARCH_MODE " + std::to_string(variant.mode));
  defines.push_back(std::string("MARCH_SKIP_EMPTY ") + (variant.skipEmpty ? "1" : "0"));
  defines.push_back(std::string("MARCH_PREINTEGRATED ") + (variant.preintegrated ? "1" : "0"));
  defines.push_back(std::string("MARCH_STEP_RULE ") + (variant.stepRule ? "1" : "0"));
  defines.push_back(std::string("MARCH_ADAPTIVE ") + (variant.adaptive ? "1" : "0"));
  defines.push_back(std::string("MARCH_COLUMNS ") + (variant.columns ? "1" : "0"));
  defines.push_back(std::string("MARCH_COUNT ") + (variant.countSamples ? "1" : "0"));
  defines.push_back("VOLUME_COUNT " + std::to_string(variant.volumes.size()));
  auto program = ShaderProgramGL::createFromSource("fullscreen.vert", "volume_march.frag", source, defines);
  if (!program) return fail(program.error());
  ProgramEntry entry{std::move(*program), UniformCacheGL(), {}, {}, {}};
  const GLuint id = entry.program.id();
  entry.uniforms = UniformCacheGL(id);
  auto location = [id](const std::string& name) { return glGetUniformLocation(id, name.c_str()); };
  MarchLocationsGL& l = entry.locations;
  l.cameraToEcef = location("u_cameraToEcef");
  l.focalPx = location("u_focalPx");
  l.imageSizePx = location("u_imageSizePx");
  l.near = location("u_near");
  l.step = location("u_step");
  l.earlyTermination = location("u_earlyTermination");
  l.debugT = location("u_debugT");
  l.coarseSizePx = location("u_coarseSizePx");
  l.refineThreshold = location("u_refineThreshold");
  l.columnBox = location("u_columnBox");
  l.columnHeights = location("u_columnHeights");
  l.columnAnchor = location("u_columnAnchor");
  // Texture units are fixed per program: set once.
  glProgramUniform1i(id, location("u_globeDepth"), kDepthUnit);
  glProgramUniform1i(id, location("u_transfer"), kTransferUnit);
  glProgramUniform1i(id, location("u_tfIntegral"), kIntegralUnit);
  if (variant.adaptive) glProgramUniform1i(id, location("u_coarse"), kCoarseUnit);
  for (std::size_t k = 0; k < variant.volumes.size(); ++k) {
    const std::string p = volumePrefix(k);
    auto v = [&](const char* name) { return location(std::string(p).append(name)); };
    l.volumes.push_back({v("eyeRel"), v("ecefToLocal"), v("gridMinLocal"), v("gridCellSize"), v("gridCells"),
                         v("isoValue"), v("opacityZeroValue"), v("mipVisibleMin"), v("tfRange"), v("isoColor"),
                         v("samplesPerCell"), v("hole")});
    glProgramUniform1i(id, v("grid"), gridUnit(static_cast<int>(k)));
  }
  entry.slots.resize(variant.volumes.size());
  return &programs_.emplace(variant, std::move(entry)).first->second.program;
}

void VolumeRendererGL::ensureTarget(int widthPx, int heightPx, GLenum format) {
  if (volumeTarget_ && volumeTarget_->widthPx() == widthPx && volumeTarget_->heightPx() == heightPx &&
      volumeFormat_ == format) {
    return;
  }
  auto t = FramebufferGL::create(widthPx, heightPx, format);
  assert(t);
  if (lastImage_ == volumeTarget_.get()) lastImage_ = nullptr;
  volumeTarget_ = std::move(*t);
  volumeFormat_ = format;
}

bool VolumeRendererGL::march(const Camera& camera, const VolumeLayerGL* layers, int count, GLuint depthTexture,
                             int debugMode, double debugT, const CoarseGL* coarse, const ColumnsGL* columns) {
  using C = MarchConstants;
  const VolumeRenderOptions& first = layers[0].options;
  const volume::VolumeRenderSettings& rs = first.render;
  const int mode = modeIndex(rs.mode);
  const bool coordinates = debugMode == 1;
  const bool preintegrated = !coordinates && mode == 0 && first.classification == Classification::Preintegrated;
  MarchVariant variant;
  variant.mode = coordinates ? 3 : mode;
  variant.skipEmpty = first.skipEmptySpace;
  variant.preintegrated = preintegrated;
  variant.adaptive = coarse != nullptr && !debugMode;
  variant.columns = columns != nullptr && !debugMode;
  variant.countSamples = debugMode == 2;
  for (int k = 0; k < count; ++k) {
    variant.volumes.emplace_back(std::string(layers[k].volume->samplerShaderFile()),
                                 layers[k].volume->samplerDefines(layers[k].options));
    // Columns take the fixed step (their samples are made once and kept).
    variant.stepRule = variant.stepRule ||
                       (!coordinates && !variant.columns && layers[k].options.render.samplesPerCell > 0.0);
  }
  // The step rule never goes above a pixel's footprint t / focal: where the volumes' far side is
  // nearer than 2 steps' worth of footprint, every level is 0 and the fixed-step program draws the
  // same picture without the rule's cost per sample.
  if (variant.stepRule) {
    double farMeters = 0.0;
    for (int k = 0; k < count; ++k) {
      const volume::BoundingSphere b = layers[k].volume->referenceSampler().boundingSphere();
      farMeters = std::max(farMeters, glm::length(b.centreEcef - camera.eyeEcef()) + b.radiusMeters);
    }
    if (farMeters / camera.focalLengthPx() < 2.0 * rs.stepMeters) variant.stepRule = false;
  }
  if (!marchProgram(variant)) return false;
  ProgramEntry& entry = programs_.find(variant)->second;
  entry.program.use();
  const MarchLocationsGL& loc = entry.locations;

  // Shared: camera, step, termination (set only when one of them changed).
  const glm::mat3 cameraToEcef(camera.cameraToEcef());
  std::vector<float> shared(glm::value_ptr(cameraToEcef), glm::value_ptr(cameraToEcef) + 9);
  shared.insert(shared.end(), {static_cast<float>(camera.focalLengthPx()), static_cast<float>(camera.widthPx()),
                               static_cast<float>(camera.heightPx()), static_cast<float>(camera.nearMeters()),
                               static_cast<float>(rs.stepMeters), static_cast<float>(rs.earlyTerminationAlpha),
                               static_cast<float>(debugT)});
  if (variant.adaptive)
    shared.insert(shared.end(), {static_cast<float>(coarse->sizePx.x), static_cast<float>(coarse->sizePx.y),
                                 static_cast<float>(coarse->thresholdSteps / 255.0)});
  if (shared != entry.shared) {
    glUniformMatrix3fv(loc.cameraToEcef, 1, GL_FALSE, shared.data());
    glUniform1f(loc.focalPx, shared[9]);
    glUniform2f(loc.imageSizePx, shared[10], shared[11]);
    glUniform1f(loc.near, shared[12]);
    glUniform1f(loc.step, shared[13]);
    glUniform1f(loc.earlyTermination, shared[14]);
    glUniform1f(loc.debugT, shared[15]);
    uniformUploads_ += 7;
    if (variant.adaptive) {
      glUniform2f(loc.coarseSizePx, shared[16], shared[17]);
      glUniform1f(loc.refineThreshold, shared[18]);
      uniformUploads_ += 2;
    }
    entry.shared = std::move(shared);
  }
  if (variant.columns) {
    // Set every call: each slab has its own heights.
    glUniform4fv(loc.columnBox, 1, glm::value_ptr(columns->box));
    glUniform2fv(loc.columnHeights, 1, glm::value_ptr(columns->heights));
    glUniform3fv(loc.columnAnchor, 1, glm::value_ptr(columns->anchor));
    uniformUploads_ += 3;
  }
  if (variant.adaptive) glBindTextureUnit(kCoarseUnit, coarse->texture);
  glBindTextureUnit(kDepthUnit, depthTexture);
  glBindTextureUnit(kTransferUnit, transfer_);
  glBindTextureUnit(kIntegralUnit, transferIntegral_);

  for (int k = 0; k < count; ++k) {
    const VolumeGL& vol = *layers[k].volume;
    const VolumeRenderOptions& o = layers[k].options;
    const MarchLocationsGL::Volume& vl = loc.volumes[static_cast<std::size_t>(k)];
    ProgramEntry::Slot& slot = entry.slots[static_cast<std::size_t>(k)];
    const volume::VolumeRenderSettings& s = o.render;
    const auto& stops = s.transfer.colors.stops();
    // Transfer function tabulated over the volume's value range (TRANSFER_ENTRIES entries; the
    // value is quantised to (max - min) / 4096, ~0.03 dBZ for reflectivity). For DVR the opacity
    // is already corrected for the step (1 - (1 - alpha)^(step / reference), in double here
    // instead of a pow per sample on the GPU); pre-integrated DVR takes the extinction per metre
    // instead (the shader needs paths of a step and of half a step) and the cumulative
    // integrals; MIP and iso use the table's alpha. Uploaded only when the row changes.
    const volume::ValueRange range = vol.valueRange();
    const double tfLo = std::min(range.minValue, s.isoValue) - 1.0;
    const double tfHi = std::max(range.maxValue, s.isoValue) + 1.0;
    std::vector<double> fingerprint{tfLo, tfHi, static_cast<double>(mode), preintegrated ? 1.0 : 0.0, s.stepMeters};
    appendTransferKey(s.transfer, fingerprint);
    TransferKey key{&s.transfer, fingerprint};
    if (!(transferRows_[k] == key)) {
      std::vector<glm::vec4> table(C::kTransferEntries);
      for (int i = 0; i < C::kTransferEntries; ++i) {
        const double value = tfLo + (i + 0.5) / C::kTransferEntries * (tfHi - tfLo);
        glm::dvec4 c = s.transfer.classify(value);
        if (preintegrated) {
          c.a = s.transfer.extinctionPerMeter(c.a);
        } else if (mode == 0) {
          c.a = s.transfer.correctedOpacity(c.a, s.stepMeters);
        }
        table[i] = glm::vec4(c);
      }
      glTextureSubImage2D(transfer_, 0, 0, k, C::kTransferEntries, 1, GL_RGBA, GL_FLOAT, table.data());
      if (preintegrated) {
        const std::vector<glm::dvec4> integral =
            volume::transferIntegralTable(s.transfer, tfLo, tfHi, C::kTransferEntries);
        const std::vector<glm::vec4> narrowed(integral.begin(), integral.end());
        glTextureSubImage2D(transferIntegral_, 0, 0, k, C::kTransferEntries + 1, 1, GL_RGBA, GL_FLOAT, narrowed.data());
      }
      transferRows_[k] = std::move(key);
    }

    // The volume's generic uniforms: the eye relative to its origin (subtracted in double, then
    // narrowed), its grid's frame relative to that origin (ECEF axes), iso value, the value
    // below which nothing shows, the transfer table's range.
    const volume::OccupancyGrid& grid = vol.occupancy().grid();
    const glm::mat3 ecefToLocal(glm::transpose(grid.localToEcef));
    const glm::dvec3 shift = glm::transpose(grid.localToEcef) * (vol.originEcef() - grid.originEcef);
    const glm::vec3 eyeRel(camera.eyeEcef() - vol.originEcef());
    const glm::vec3 gridMin(grid.minLocal - shift), cellSize(grid.cellSizeMeters);
    // MIP: a maximum below the colour table's first stop is transparent, so cells below it can be skipped too.
    const double firstVisible =
        stops.empty() ? -1e30 : (stops.front().value - s.transfer.colors.offset()) / s.transfer.colors.scale();
    std::vector<float> generic(glm::value_ptr(ecefToLocal), glm::value_ptr(ecefToLocal) + 9);
    generic.insert(
        generic.end(),
        {eyeRel.x, eyeRel.y, eyeRel.z, gridMin.x, gridMin.y, gridMin.z, cellSize.x, cellSize.y, cellSize.z,
         static_cast<float>(grid.cells.x), static_cast<float>(grid.cells.y), static_cast<float>(grid.cells.z),
         static_cast<float>(s.isoValue), static_cast<float>(s.transfer.opacityZeroValue),
         static_cast<float>(firstVisible), static_cast<float>(tfLo), static_cast<float>(tfHi)});
    // The isosurface's colour, classified exactly here (the table quantises values to
    // (max - min) / TRANSFER_ENTRIES, which at a stepped table's band edge picks the band below).
    const glm::dvec4 isoColor = s.transfer.classify(s.isoValue);
    generic.insert(generic.end(), {static_cast<float>(isoColor.r), static_cast<float>(isoColor.g),
                                   static_cast<float>(isoColor.b), static_cast<float>(s.samplesPerCell)});
    // The hole (VolumeLayerGL::hole): west, span, south, north (deg); span -1: none.
    const std::optional<volume::LonLatBox>& hole = layers[k].hole;
    generic.insert(
        generic.end(),
        {hole ? static_cast<float>(hole->westDeg) : 0.0f, hole ? static_cast<float>(hole->spanDeg) : -1.0f,
         hole ? static_cast<float>(hole->southDeg) : 0.0f, hole ? static_cast<float>(hole->northDeg) : 0.0f});
    if (generic != slot.generic) {
      glUniformMatrix3fv(vl.ecefToLocal, 1, GL_FALSE, generic.data());
      glUniform3fv(vl.eyeRel, 1, generic.data() + 9);
      glUniform3fv(vl.gridMinLocal, 1, generic.data() + 12);
      glUniform3fv(vl.gridCellSize, 1, generic.data() + 15);
      glUniform3iv(vl.gridCells, 1, glm::value_ptr(grid.cells));
      glUniform1f(vl.isoValue, generic[21]);
      glUniform1f(vl.opacityZeroValue, generic[22]);
      glUniform1f(vl.mipVisibleMin, generic[23]);
      glUniform2f(vl.tfRange, generic[24], generic[25]);
      glUniform3fv(vl.isoColor, 1, generic.data() + 26);
      glUniform1f(vl.samplesPerCell, generic[29]);
      glUniform4fv(vl.hole, 1, generic.data() + 30);
      uniformUploads_ += 12;
      slot.generic = std::move(generic);
    }
    glBindTextureUnit(static_cast<GLuint>(gridUnit(k)), vol.occupancy().texture());
    const SamplerBindingGL binding{&entry.uniforms, volumePrefix(static_cast<std::size_t>(k)), samplerFirstUnit(k),
                                   nearestSampler_, static_cast<int>(k)};
    if (slot.volumeId != vol.id() || slot.uniformVersion != vol.uniformVersion()) {
      vol.setSamplerUniforms(binding);
      ++uniformUploads_;  // counted once per volume (a handful of glUniform calls)
      slot.volumeId = vol.id();
      slot.uniformVersion = vol.uniformVersion();
    }
    vol.bindSamplerTextures(binding, o);
  }
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  for (int i = kFirstVolumeUnit; i < gridUnit(count); ++i) glBindSampler(static_cast<GLuint>(i), 0);
  glBindVertexArray(0);
  return true;
}

std::size_t VolumeRendererGL::groupEnd(const std::vector<VolumeLayerGL>& layers, std::size_t begin) {
  const VolumeRenderOptions& a = layers[begin].options;
  std::size_t end = begin + 1;
  while (end < layers.size() && end - begin < static_cast<std::size_t>(MarchConstants::kMaxVolumes)) {
    const VolumeRenderOptions& b = layers[end].options;
    if (b.render.mode != a.render.mode || b.render.stepMeters != a.render.stepMeters ||
        b.render.earlyTerminationAlpha != a.render.earlyTerminationAlpha || b.classification != a.classification ||
        b.skipEmptySpace != a.skipEmptySpace || b.imageScale != a.imageScale || b.refineThreshold != a.refineThreshold)
      break;
    ++end;
  }
  return end;
}

std::vector<VolumeRendererGL::PassGL> VolumeRendererGL::planPasses(const Camera& camera,
                                                                   const std::vector<VolumeLayerGL>& layers) {
  std::vector<volume::BoundingSphere> spheres;
  for (const VolumeLayerGL& l : layers) spheres.push_back(l.volume->referenceSampler().boundingSphere());
  std::vector<volume::VolumeCluster> clusters = volume::clusterBySphere(spheres);
  volume::sortBackToFront(clusters, camera.eyeEcef());
  const volume::RenderCamera rc = referenceCameraFor(camera);
  const int w = camera.widthPx(), h = camera.heightPx();
  std::vector<PassGL> passes;
  for (const volume::VolumeCluster& c : clusters) {
    // The cluster's screen rectangle: the projected corners of the cube around its sphere (all
    // in front of the eye: the cube's projection, which holds the sphere's, is their hull), one
    // pixel wider; the whole image if a corner is not in front.
    glm::ivec4 rect(0, 0, w, h);
    glm::dvec2 lo(1e300), hi(-1e300);
    bool inFront = true;
    for (int corner = 0; corner < 8 && inFront; ++corner) {
      const glm::dvec3 sign((corner & 1) ? 1.0 : -1.0, (corner & 2) ? 1.0 : -1.0, (corner & 4) ? 1.0 : -1.0);
      const auto px = volume::projectToPixel(rc, c.enclosing.centreEcef + sign * c.enclosing.radiusMeters);
      if (!px) {
        inFront = false;
      } else {
        lo = glm::min(lo, *px);
        hi = glm::max(hi, *px);
      }
    }
    if (inFront) {
      const double x0 = std::clamp(std::floor(lo.x) - 1.0, 0.0, double(w)),
                   x1 = std::clamp(std::ceil(hi.x) + 1.0, 0.0, double(w));
      const double y0 = std::clamp(std::floor(lo.y) - 1.0, 0.0, double(h)),
                   y1 = std::clamp(std::ceil(hi.y) + 1.0, 0.0, double(h));
      // Pixel rows from the top -> GL rows from the bottom.
      rect = glm::ivec4(int(x0), h - int(y1), int(x1 - x0), int(y1 - y0));
    }
    if (rect.z <= 0 || rect.w <= 0) continue;  // off screen
    std::vector<VolumeLayerGL> members;
    for (std::size_t i : c.members) members.push_back(layers[i]);
    for (std::size_t begin = 0, end = 0; begin < members.size(); begin = end) {
      end = groupEnd(members, begin);
      passes.push_back(PassGL{std::vector<VolumeLayerGL>(members.begin() + static_cast<std::ptrdiff_t>(begin),
                                                         members.begin() + static_cast<std::ptrdiff_t>(end)),
                              rect});
    }
  }
  return passes;
}

void VolumeRendererGL::compositeOver(GLuint volumeTexture, const FramebufferGL& target, const glm::ivec4& rectPx) {
  target.bind();
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_SCISSOR_TEST);
  glScissor(rectPx.x, rectPx.y, rectPx.z, rectPx.w);
  composite_.use();
  glBindTextureUnit(0, volumeTexture);
  glUniform1i(composite_.uniform("u_volume"), 0);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
}

namespace {

// What a frame's volumes are: the camera, the frame size, each layer's volume and settings (with
// or without the image scale), and the far-field slab sets made so far.
constexpr std::size_t kProgressKeyFarFieldSets = 9;  // after the camera's 3 x 3 rotation
std::vector<double> progressKey(const Camera& camera, const std::vector<VolumeLayerGL>& layers,
                                const FramebufferGL& target, bool withScale, std::size_t farFieldSets) {
  std::vector<double> key(glm::value_ptr(camera.cameraToEcef()), glm::value_ptr(camera.cameraToEcef()) + 9);
  key.push_back(double(farFieldSets));  // at kProgressKeyFarFieldSets
  key.insert(key.end(), {camera.eyeEcef().x, camera.eyeEcef().y, camera.eyeEcef().z, camera.focalLengthPx(),
                         camera.nearMeters(), double(target.widthPx()), double(target.heightPx())});
  for (const VolumeLayerGL& l : layers) {
    const volume::VolumeRenderSettings& r = l.options.render;
    key.insert(key.end(),
               {double(l.volume->id()), double(l.volume->uniformVersion()), withScale ? l.options.imageScale : 0.0,
                withScale ? l.options.refineThreshold : -1.0, double(l.options.skipEmptySpace),
                double(l.options.classification), double(l.options.farField), double(r.mode), double(r.interpolation),
                r.stepMeters, r.earlyTerminationAlpha, r.isoValue, r.transfer.opacityZeroValue,
                r.transfer.opacityFullValue, r.transfer.maxOpacity, r.transfer.opacityReferenceMeters});
    for (const glm::dvec2& q : r.transfer.opacityPoints) key.insert(key.end(), {q.x, q.y});
  }
  return key;
}

// A pass's volume image size at an image scale.
glm::ivec2 volumeImageSize(const FramebufferGL& target, double imageScale) {
  const double scale = std::clamp(imageScale, 0.05, 1.0);
  return {std::max(1, static_cast<int>(std::lround(target.widthPx() * scale))),
          std::max(1, static_cast<int>(std::lround(target.heightPx() * scale)))};
}

// A far-field view's rectangle (pixels, rows from the top: x0, y0, x1, y1) within a pass's
// rectangle (GL: x, y from the bottom left, width, height), as a GL rectangle.
glm::ivec4 farFieldRectGL(const glm::dvec4& rectPx, const glm::ivec4& passRect, const FramebufferGL& target) {
  const int x0 = std::max(passRect.x, static_cast<int>(std::floor(std::max(rectPx.x, -1e6))));
  const int x1 = std::min(passRect.x + passRect.z, static_cast<int>(std::ceil(std::min(rectPx.z, 1e6))));
  const int y0 = std::max(passRect.y, static_cast<int>(std::floor(target.heightPx() - std::min(rectPx.w, 1e6))));
  const int y1 =
      std::min(passRect.y + passRect.w, static_cast<int>(std::ceil(target.heightPx() - std::max(rectPx.y, -1e6))));
  return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

// The pass's rectangle in a w x h volume image (x0, y0, x1, y1), two texels wider: the
// composite's bilinear lookups inside the frame rectangle read only texels cleared and marched.
glm::ivec4 volumeImageBox(const glm::ivec4& rectPx, const FramebufferGL& target, glm::ivec2 size) {
  const double sx = double(size.x) / target.widthPx(), sy = double(size.y) / target.heightPx();
  return {std::max(0, int(std::floor(rectPx.x * sx)) - 2), std::max(0, int(std::floor(rectPx.y * sy)) - 2),
          std::min(size.x, int(std::ceil((rectPx.x + rectPx.z) * sx)) + 2),
          std::min(size.y, int(std::ceil((rectPx.y + rectPx.w) * sy)) + 2)};
}

}  // namespace

VolumeRendererGL::FarFieldChoice VolumeRendererGL::chooseFarField(const Camera& camera,
                                                                  const std::vector<VolumeLayerGL>& layers) {
  // One volume seen from far enough: its far field (FarFieldGL.h) instead of the march.
  FarFieldChoice c;
  if (layers.size() == 1) c.plan = FarFieldGL::planFor(camera, layers[0]);
  c.hidden = c.plan && !c.plan->view.rect;  // all of it behind the Earth
  if (c.plan && !c.hidden && !farField_->prepare(*this, layers[0], *c.plan)) c.plan.reset();
  return c;
}

bool VolumeRendererGL::marchBox(const Camera& camera, const std::vector<VolumeLayerGL>& layers,
                                const FramebufferGL& image, const glm::ivec4& box, const FramebufferGL& target,
                                const CoarseGL* coarse, const FarFieldChoice* farField) {
  const FarFieldChoice chosen = farField ? *farField : chooseFarField(camera, layers);
  const std::optional<FarFieldPlan>& plan = chosen.plan;
  const bool hidden = chosen.hidden;
  image.bind();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glEnable(GL_SCISSOR_TEST);
  glScissor(box.x, box.y, box.z - box.x, box.w - box.y);
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  bool ok = true;
  if (hidden) {
    // Nothing of it can be seen.
  } else if (plan) {
    farField_->draw(camera, layers[0], plan->view, target.depthTexture());
  } else {
    ok = march(camera, layers.data(), static_cast<int>(layers.size()), target.depthTexture(), 0, 0.0, coarse);
  }
  glDisable(GL_SCISSOR_TEST);
  return ok;
}

bool VolumeRendererGL::marchColumns(const VolumeLayerGL& layer, const FarFieldPlan& plan, int slab) {
  const double lonMid = plan.westDeg + 0.5 * plan.columns * plan.lonStepDeg;
  const double latMid = plan.southDeg + 0.5 * plan.rows * plan.latStepDeg;
  const double top = plan.boundariesMeters[static_cast<std::size_t>(slab)];
  const double bottom = plan.boundariesMeters[static_cast<std::size_t>(slab) + 1];
  // The volumes' "eye" is a point above the middle of the grid (only its ECEF position is used).
  CameraPose pose;
  pose.latDeg = latMid;
  pose.lonDeg = lonMid;
  pose.heightMeters = top;
  const Camera anchor(pose, 60.0, plan.columns, plan.rows);
  ColumnsGL columns;
  columns.box = glm::vec4(static_cast<float>(plan.westDeg), static_cast<float>(plan.southDeg),
                          static_cast<float>(plan.lonStepDeg), static_cast<float>(plan.latStepDeg));
  columns.heights = glm::vec2(static_cast<float>(top), static_cast<float>(bottom));
  columns.anchor = glm::vec3(anchor.eyeEcef());
  return march(anchor, &layer, 1, emptyDepth_, 0, 0.0, nullptr, &columns);
}

bool VolumeRendererGL::farFieldPending() const { return farField_->pending(); }

glm::ivec4 VolumeRendererGL::overRectOf(const Camera& camera, const PassGL& pass, const FramebufferGL& target,
                                        const FarFieldChoice* farField) {
  if (refines(pass.layers[0].options)) return pass.rectPx;
  std::optional<FarFieldPlan> plan;
  if (farField) {
    if (farField->hidden) return glm::ivec4(0);
    plan = farField->plan;
  } else if (pass.layers.size() == 1) {
    plan = FarFieldGL::planFor(camera, pass.layers[0]);
    if (plan && !plan->view.rect) return glm::ivec4(0);  // all of it behind the Earth
  }
  // Drawn from its far field, only the far field's rectangle can hold anything: the image is
  // laid over the frame there only (the continental view's cluster: 0.46 instead of 0.92
  // megapixels at 1280x720).
  return plan && plan->view.rect ? farFieldRectGL(*plan->view.rect, pass.rectPx, target) : pass.rectPx;
}

void VolumeRendererGL::draw(const Camera& camera, const std::vector<VolumeLayerGL>& layers,
                            const FramebufferGL& target) {
  farField_->beginFrame(farFieldBuildBudgetMs_);
  const std::vector<PassGL> passes = planPasses(camera, layers);
  // One pass: its volume image stays in volumeTarget_ (drawProgressive's preview may take it).
  lastDrawValid_ = passes.size() == 1;
  for (const PassGL& pass : passes) {
    const VolumeRenderOptions& o = pass.layers[0].options;
    const FarFieldChoice farField = chooseFarField(camera, pass.layers);
    const glm::ivec4 overRect = overRectOf(camera, pass, target, &farField);
    const glm::ivec2 size = volumeImageSize(target, o.imageScale);
    ensureTarget(size.x, size.y, GL_RGBA16F);
    bool ok = marchBox(camera, pass.layers, *volumeTarget_, volumeImageBox(pass.rectPx, target, size), target, nullptr,
                       &farField);
    lastImage_ = volumeTarget_.get();
    if (ok && refines(o)) {
      // Adaptive refinement: the small image just marched, then the frame-sized pass over it.
      const glm::ivec2 full = volumeImageSize(target, 1.0);
      if (!refineTarget_ || refineTarget_->widthPx() != full.x || refineTarget_->heightPx() != full.y) {
        auto t = FramebufferGL::create(full.x, full.y, GL_RGBA16F);
        assert(t);
        if (lastImage_ == refineTarget_.get()) lastImage_ = nullptr;
        refineTarget_ = std::move(*t);
      }
      const CoarseGL coarse{volumeTarget_->colorTexture(), size, o.refineThreshold};
      ok = marchBox(camera, pass.layers, *refineTarget_, volumeImageBox(pass.rectPx, target, full), target, &coarse);
      lastImage_ = refineTarget_.get();
    }
    if (ok) {
      if (overRect.z > 0 && overRect.w > 0) compositeOver(lastImage_->colorTexture(), target, overRect);
    } else {
      target.bind();
      glEnable(GL_DEPTH_TEST);
    }
  }
  // After the passes: a far field they completed is part of what the image is.
  if (lastDrawValid_) lastDrawKey_ = progressKey(camera, layers, target, true, farField_->slabSetsMade());
}

bool VolumeRendererGL::drawProgressive(const Camera& camera, const std::vector<VolumeLayerGL>& layers,
                                       const FramebufferGL& target, double budgetMs) {
  // The frame's volume work is bounded by `budgetMs` in all: what the frame queued before (the
  // globe, or the kept background) is finished first and counts against it, and so do the slabs
  // and the preview made in this call; at least a quarter of it is left to each of slabs and tiles.
  const auto frameStart = std::chrono::steady_clock::now();
  glFinish();
  const auto leftMs = [&] {
    const double spent =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frameStart).count();
    return std::max(budgetMs - spent, 0.25 * budgetMs);
  };
  const std::vector<PassGL> passes = planPasses(camera, layers);
  // Slabs made over frames take the refinement's time, and the tiles wait for them (marched now,
  // they would be drawn again from the far field). A set completed starts the refinement again:
  // the refined frame is then draw()'s, drawn from it.
  // (Without a budget, one tile a call, they take the far field's own.)
  farField_->beginFrame(farFieldBuildBudgetMs_ > 0.0 ? (budgetMs > 0.0 ? leftMs() : farFieldBuildBudgetMs_) : 0.0);
  advanceFarFields(camera, passes);
  const bool slabsPending = farField_->pending();
  const std::vector<double> key = progressKey(camera, layers, target, true, farField_->slabSetsMade());
  Progress& p = progress_;
  const bool lastDrawValid = lastDrawValid_;
  lastDrawValid_ = false;
  // A far-field set completed before any tile was marched changes nothing drawn yet: the preview
  // stays (marched again, a network's preview took 0.4-0.6 s at a quarter of 1280x720).
  const auto sameButFarFieldSets = [&](const std::vector<double>& a) {
    const auto at = static_cast<std::ptrdiff_t>(kProgressKeyFarFieldSets);
    return a.size() == key.size() && std::equal(a.begin(), a.begin() + at, key.begin()) &&
           std::equal(a.begin() + at + 1, a.end(), key.begin() + at + 1);
  };
  if (p.valid && p.next == 0 && p.images.size() == passes.size() && sameButFarFieldSets(p.key)) p.key = key;
  if (!p.valid || p.key != key) {
    p = Progress{};
    p.valid = true;
    p.key = key;
    for (std::size_t i = 0; i < passes.size(); ++i) {
      const PassGL& pass = passes[i];
      const VolumeRenderOptions& o = pass.layers[0].options;
      const bool adaptive = refines(o);
      const glm::ivec2 size = volumeImageSize(target, adaptive ? 1.0 : o.imageScale);
      auto image = FramebufferGL::create(size.x, size.y, GL_RGBA16F);
      if (!image) return false;
      // The preview, stretched over the image: `previewImage` (its `small` corner) holds it.
      std::unique_ptr<FramebufferGL> coarse;
      const FramebufferGL* previewImage = nullptr;
      glm::ivec2 small{0};
      bool ok = true;
      if (adaptive) {
        // Adaptive refinement: its small image, marched whole as draw() marches it, is the
        // preview; the tiles are the refinement pass's.
        small = volumeImageSize(target, o.imageScale);
        auto made = FramebufferGL::create(small.x, small.y, GL_RGBA16F);
        if (!made) return false;
        coarse = std::move(*made);
        const auto start = std::chrono::steady_clock::now();
        ok = marchBox(camera, pass.layers, *coarse, volumeImageBox(pass.rectPx, target, small), target);
        glFinish();
        p.marchedMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        previewImage = coarse.get();
      } else {
        // The pass marched at previewScale_ (as draw() would). The frame just drawn by draw() at
        // that scale (the viewer's last moving frame, the camera now at rest) already holds it.
        std::vector<VolumeLayerGL> preview = pass.layers;
        for (VolumeLayerGL& l : preview) {
          l.options.imageScale = std::min(l.options.imageScale, previewScale_);
          l.options.refineThreshold = -1.0;  // as the viewer's moving frames
        }
        small = volumeImageSize(target, preview[0].options.imageScale);
        if (passes.size() == 1 && lastDrawValid && volumeTarget_ &&
            lastDrawKey_ == progressKey(camera, preview, target, true, farField_->slabSetsMade())) {
          ++previewsReused_;
        } else {
          // Within the frame's budget (shared by the passes) at the last preview's cost a pixel,
          // and at the least scale while no cost is known: a network whose far field is being
          // made, or a view first seen, would otherwise march for hundreds of milliseconds here
          // (159 radars at a quarter of 1280x720: 0.3-0.6 s).
          const double passPixels = double(pass.rectPx.z) * double(pass.rectPx.w);
          const double scaleNow = preview[0].options.imageScale;
          if (budgetMs > 0.0 && passPixels > 0.0) {
            const double fits = previewMsPerPixel_ > 0.0
                                    ? std::sqrt(budgetMs / double(passes.size()) / (previewMsPerPixel_ * passPixels))
                                    : kMinPreviewScale;
            if (fits < scaleNow)
              for (VolumeLayerGL& l : preview) l.options.imageScale = std::max(kMinPreviewScale, fits);
            small = volumeImageSize(target, preview[0].options.imageScale);
          }
          ensureTarget(small.x, small.y, GL_RGBA16F);
          ++previewsMarched_;
          lastPreviewScale_ = preview[0].options.imageScale;
          const auto previewStart = std::chrono::steady_clock::now();
          ok = marchBox(camera, preview, *volumeTarget_, volumeImageBox(pass.rectPx, target, small), target);
          glFinish();
          const double previewMs =
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - previewStart).count();
          const double marched = passPixels * preview[0].options.imageScale * preview[0].options.imageScale;
          if (ok && marched >= 1.0) previewMsPerPixel_ = previewMs / marched;
          const double scale = preview[0].options.imageScale / std::max(1e-6, o.imageScale);
          if (ok && passes.size() == 1 && scale > 0.0)
            fullMarchEstimateMs_ =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - previewStart).count() /
                (scale * scale);
        }
        previewImage = volumeTarget_.get();
      }
      (*image)->bind();
      glClearColor(0, 0, 0, 0);
      glClear(GL_COLOR_BUFFER_BIT);
      if (ok)
        glBlitNamedFramebuffer(previewImage->id(), (*image)->id(), 0, 0, small.x, small.y, 0, 0, size.x, size.y,
                               GL_COLOR_BUFFER_BIT, GL_LINEAR);
      // The tiles of the box draw() marches, row by row from the top of the picture, within where
      // the pass's image can hold anything (a far field's rectangle: overRectOf).
      const glm::ivec4 over = overRectOf(camera, pass, target, nullptr);
      p.overRects.push_back(over);
      const glm::ivec4 box = volumeImageBox(over, target, size);
      if (over.z > 0 && over.w > 0)
        for (int y1 = box.w; y1 > box.y; y1 -= kTilePx)
          for (int x0 = box.x; x0 < box.z; x0 += kTilePx)
            p.tiles.push_back({i, glm::ivec4(x0, std::max(box.y, y1 - kTilePx), std::min(box.z, x0 + kTilePx), y1)});
      p.coarse.push_back(std::move(coarse));
      p.images.push_back(std::move(*image));
    }
  }
  // Tiles until the budget is spent (at least one), each as draw() marches its box. What the frame
  // did before (the queued globe, the preview, slabs) counts against the budget, but at least a
  // quarter of the budget goes to tiles: counted into the first tile's time, it left one tile a
  // frame whatever its cost (159 radars from afar: 1,016 tiles of 0.3-0.5 ms each, the first timed
  // at 25-33 ms, refined in over 1,000 frames).
  glFinish();  // the preview's march, if any, counted
  const double tileBudgetMs = leftMs();
  const auto start = std::chrono::steady_clock::now();
  for (bool first = true; !slabsPending && p.next < p.tiles.size(); first = false) {
    if (!first &&
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() >= tileBudgetMs)
      break;
    const Progress::Tile& tile = p.tiles[p.next++];
    const auto tileStart = std::chrono::steady_clock::now();
    const FramebufferGL* small = p.coarse[tile.pass].get();
    const CoarseGL coarse{small ? small->colorTexture() : 0u,
                          small ? glm::ivec2(small->widthPx(), small->heightPx()) : glm::ivec2(0),
                          passes[tile.pass].layers[0].options.refineThreshold};
    marchBox(camera, passes[tile.pass].layers, *p.images[tile.pass], tile.box, target, small ? &coarse : nullptr);
    glFinish();  // the time taken, not the time to queue
    p.marchedMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tileStart).count();
    if (p.next == p.tiles.size()) fullMarchEstimateMs_ = p.marchedMs;
  }
  for (std::size_t i = 0; i < passes.size() && i < p.images.size() && i < p.overRects.size(); ++i)
    if (p.overRects[i].z > 0 && p.overRects[i].w > 0)
      compositeOver(p.images[i]->colorTexture(), target, p.overRects[i]);
  target.bind();
  glEnable(GL_DEPTH_TEST);
  return !slabsPending && p.next == p.tiles.size();
}

void VolumeRendererGL::advanceFarFields(const Camera& camera, const std::vector<PassGL>& passes) {
  for (const PassGL& pass : passes) {
    if (pass.layers.size() != 1) continue;  // as marchBox: the far field serves one volume alone
    const std::optional<FarFieldPlan> plan = FarFieldGL::planFor(camera, pass.layers[0]);
    if (plan && plan->view.rect) farField_->prepare(*this, pass.layers[0], *plan);
  }
}

static std::vector<double> occluderDistancesGL(const Camera& camera, const FramebufferGL& target) {
  const int w = target.widthPx(), h = target.heightPx();
  std::vector<float> depth(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  glGetTextureImage(target.depthTexture(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                    static_cast<GLsizei>(depth.size() * sizeof(float)), depth.data());
  const volume::RenderCamera rc = referenceCameraFor(camera);
  const glm::dvec3 forward = -rc.cameraToEcef[2];
  std::vector<double> out(depth.size(), std::numeric_limits<double>::infinity());
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      // GL row 0 is the bottom; the reference's row 0 is the top.
      const float d =
          depth[static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
      if (!(d > 0.0f)) continue;  // cleared: nothing drawn there
      // Reverse-Z: d = near / (view distance along -z); along the unit ray, divide by cos.
      const glm::dvec3 dir = volume::pixelRayDirection(rc, x + 0.5, y + 0.5);
      out[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] =
          (camera.nearMeters() / static_cast<double>(d)) / glm::dot(dir, forward);
    }
  }
  return out;
}

void VolumeRendererGL::drawReference(const Camera& camera, const std::vector<VolumeLayerGL>& layers,
                                     const FramebufferGL& target, int threads) {
  if (layers.empty()) return;
  const std::vector<double> occluders = occluderDistancesGL(camera, target);
  const volume::RenderCamera rc = referenceCameraFor(camera);
  GLuint texture = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &texture);
  glTextureStorage2D(texture, 1, GL_RGBA32F, camera.widthPx(), camera.heightPx());
  glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  for (const PassGL& pass : planPasses(camera, layers)) {
    // The marcher's passes (the reference needs one mode and step per call).
    std::vector<volume::ReferenceLayer> group;
    std::vector<std::unique_ptr<volume::SamplerOutsideBox>> holed;  // the layers' holes
    for (const VolumeLayerGL& l : pass.layers) {
      const volume::VolumeSampler* sampler = &l.volume->referenceSampler();
      if (l.hole) sampler = holed.emplace_back(std::make_unique<volume::SamplerOutsideBox>(*sampler, *l.hole)).get();
      group.push_back(volume::ReferenceLayer{sampler, l.options.render});
    }
    // Occluded by what the frame's depth holds (globe tiles, models), as the marcher is.
    lastReference_ = volume::renderReference(group, rc, occluders, false, threads);
    const int w = lastReference_.widthPx, h = lastReference_.heightPx;
    std::vector<glm::vec4> rows(lastReference_.rgbaPremultiplied.size());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        rows[static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)] =
            glm::vec4(lastReference_.at(x, y));
    glTextureSubImage2D(texture, 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, rows.data());
    compositeOver(texture, target, pass.rectPx);
  }
  glDeleteTextures(1, &texture);
}

std::vector<glm::vec4> VolumeRendererGL::readVolumeImage() const {
  std::vector<glm::vec4> out;
  const FramebufferGL* image = lastImage_ ? lastImage_ : volumeTarget_.get();
  if (!image) return out;
  const int w = image->widthPx(), h = image->heightPx();
  std::vector<glm::vec4> raw(static_cast<std::size_t>(w) * h);
  glGetTextureImage(image->colorTexture(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(raw.size() * sizeof(glm::vec4)),
                    raw.data());
  out.resize(raw.size());
  for (int y = 0; y < h; ++y) {
    std::copy_n(raw.begin() + static_cast<std::ptrdiff_t>(h - 1 - y) * w, w,
                out.begin() + static_cast<std::ptrdiff_t>(y) * w);
  }
  return out;
}

std::vector<glm::vec4> VolumeRendererGL::debugCoordinatesAt(const Camera& camera, const VolumeGL& volume,
                                                            double tMeters) {
  lastDrawValid_ = false;  // volumeTarget_ is taken
  ensureTarget(camera.widthPx(), camera.heightPx(), GL_RGBA32F);
  lastImage_ = volumeTarget_.get();
  volumeTarget_->bind();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  const VolumeLayerGL layer{&volume, VolumeRenderOptions{}};
  const bool ok = march(camera, &layer, 1, emptyDepth_, 1, tMeters);
  glEnable(GL_DEPTH_TEST);
  if (!ok) return {};
  return readVolumeImage();
}

std::vector<float> VolumeRendererGL::sampleCounts(const Camera& camera, const std::vector<VolumeLayerGL>& layers) {
  if (layers.empty()) return {};
  lastDrawValid_ = false;                                         // volumeTarget_ is taken
  ensureTarget(camera.widthPx(), camera.heightPx(), GL_RGBA32F);  // counts exact to 2^24
  lastImage_ = volumeTarget_.get();
  volumeTarget_->bind();
  glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  const bool ok = march(camera, layers.data(), static_cast<int>(layers.size()), emptyDepth_, 2, 0.0);
  glEnable(GL_DEPTH_TEST);
  if (!ok) return {};
  std::vector<float> counts;
  counts.reserve(static_cast<std::size_t>(camera.widthPx()) * static_cast<std::size_t>(camera.heightPx()));
  for (const glm::vec4& p : readVolumeImage()) counts.push_back(p.r);
  return counts;
}

}  // namespace atmoglobe::engine
