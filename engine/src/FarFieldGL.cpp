#include <atmoglobe/engine/FarFieldGL.h>

#include "LoaderGL.h"

#include <atmoglobe/engine/ShaderConstants.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/Ellipsoid.h>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace atmoglobe::engine {

namespace {

// Levels of a full GL mip chain of width x height, down to 1 x 1.
int maskLevelCount(int width, int height) {
  int levels = 1;
  while ((std::max(width, height) >> levels) > 0) ++levels;
  return levels;
}

std::vector<std::string> withDefine(std::vector<std::string> defines, const std::string& define) {
  defines.push_back(define);
  return defines;
}

}  // namespace

Result<std::unique_ptr<FarFieldGL>> FarFieldGL::create() {
  std::vector<std::string> defines = ellipsoidShaderDefines();
  defines.push_back("FAR_FIELD_MAX_SLABS " + std::to_string(kMaxSlabs));
  defines.push_back("FAR_FIELD_MAX_LEVELS " + std::to_string(kMaxLevels));
  defines.push_back("FAR_FIELD_MAX_LEVEL_SLABS " + std::to_string(kMaxLevelSlabs));
  defines.push_back("FAR_FIELD_MAX_MASK_LEVELS " + std::to_string(kMaxMaskLevels));
  auto program =
      ShaderProgramGL::create("fullscreen.vert", "far_field.frag", withDefine(defines, "FAR_FIELD_MAX_SUBPIECES 1"));
  if (!program) return program.forwardError();
  auto subPieces =
      ShaderProgramGL::create("fullscreen.vert", "far_field.frag",
                              withDefine(defines, "FAR_FIELD_MAX_SUBPIECES " + std::to_string(kMaxSubPieces)));
  if (!subPieces) return subPieces.forwardError();
  auto mask = ShaderProgramGL::create("fullscreen.vert", "far_field_mask.frag", {});
  if (!mask) return mask.forwardError();
  auto merge = ShaderProgramGL::create("fullscreen.vert", "far_field_merge.frag", {});
  if (!merge) return merge.forwardError();
  std::unique_ptr<FarFieldGL> f(new FarFieldGL());
  f->program_ = std::move(*program);
  f->subPiecesProgram_ = std::move(*subPieces);
  f->maskProgram_ = std::move(*mask);
  f->mergeProgram_ = std::move(*merge);
  glCreateVertexArrays(1, &f->vao_);
  glCreateFramebuffers(1, &f->fbo_);
  return f;
}

FarFieldGL::~FarFieldGL() {
  for (Kept& k : kept_) {
    release(k.ready);
    release(k.building);
  }
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

std::optional<FarFieldPlan> FarFieldGL::planFor(const Camera& camera, const VolumeLayerGL& layer) {
  const VolumeRenderOptions& o = layer.options;
  if (o.farField != FarField::Auto || o.render.mode != volume::VolumeRenderMode::Dvr || !layer.volume) return {};
  const std::optional<FarFieldExtent> extent = layer.volume->farFieldExtent();
  if (!extent || !(extent->topMeters > 0.0) || !(extent->eastDeg > extent->westDeg) ||
      !(extent->northDeg > extent->southDeg))
    return {};
  // The narrowest pixel over the volume: at its nearest point, no nearer than its bounding
  // sphere, nor than the eye's height above the top (nothing of it is higher).
  const volume::BoundingSphere sphere = layer.volume->referenceSampler().boundingSphere();
  const double eyeHeight = globe::ecefToGeodetic(camera.eyeEcef()).heightMeters;
  if (!(eyeHeight > extent->topMeters)) return {};
  const double nearest =
      std::max(glm::length(sphere.centreEcef - camera.eyeEcef()) - sphere.radiusMeters, eyeHeight - extent->topMeters);
  const double footprint = nearest / camera.focalLengthPx();
  if (!(footprint >= kMinFootprintMeters)) return {};

  FarFieldPlan plan;
  // Texels no wider than half the footprint (with texels a pixel wide the bilinear lookup blurs
  // what the march resolves: 38.5 against 43.5 dB in FarFieldTest): a latitude step of 0.005 deg x
  // 2^L, L the largest that keeps it under that (so that nearby views share slabs), and a
  // longitude step as wide at the box's latitude nearest the equator (narrower elsewhere).
  constexpr double kMetersPerDeg = 111320.0;
  const double wantedDeg = 0.5 * footprint / kMetersPerDeg;
  double latStep = 0.005;
  while (latStep * 2.0 <= wantedDeg) latStep *= 2.0;
  const double nearestEquator = extent->southDeg <= 0.0 && extent->northDeg >= 0.0
                                    ? 0.0
                                    : std::min(89.0, std::min(std::abs(extent->southDeg), std::abs(extent->northDeg)));
  double lonStep = std::min(360.0, latStep / std::cos(glm::radians(nearestEquator)));
  const double latSpan = extent->northDeg - extent->southDeg, lonSpan = extent->eastDeg - extent->westDeg;
  // At most kMaxTexels a side and kMaxTexelsPerSlab in all: coarser where the box needs more.
  latStep = std::max(latStep, latSpan / kMaxTexels);
  lonStep = std::max(lonStep, lonSpan / kMaxTexels);
  const double texels = std::ceil(latSpan / latStep) * std::ceil(lonSpan / lonStep);
  if (texels > kMaxTexelsPerSlab) {
    const double coarser = std::sqrt(texels / kMaxTexelsPerSlab) * 1.001;
    latStep *= coarser;
    lonStep *= coarser;
  }
  plan.westDeg = extent->westDeg;
  plan.southDeg = extent->southDeg;
  plan.latStepDeg = latStep;
  plan.lonStepDeg = lonStep;
  plan.columns = std::max(1, static_cast<int>(std::ceil(lonSpan / lonStep)));
  plan.rows = std::max(1, static_cast<int>(std::ceil(latSpan / latStep)));
  // Slabs from the top down: the volume's top, then the fixed boundaries below it.
  plan.boundariesMeters.push_back(extent->topMeters);
  for (auto it = kSlabBoundariesMeters.rbegin(); it != kSlabBoundariesMeters.rend(); ++it)
    if (*it < extent->topMeters) plan.boundariesMeters.push_back(*it);
  // A top slab less than half as thick as the one below it joins that one (a top 200 m above a
  // boundary would cost every pixel a piece for a sliver).
  std::vector<double>& b = plan.boundariesMeters;
  if (b.size() >= 3 && b[0] - b[1] < 0.5 * (b[1] - b[2])) b.erase(b.begin() + 1);
  plan.view = viewOf(camera, plan);
  double thickest = 0.0;
  for (std::size_t i = 0; i + 1 < plan.boundariesMeters.size(); ++i)
    thickest = std::max(thickest, plan.boundariesMeters[i] - plan.boundariesMeters[i + 1]);
  // Seen slantwise, a slab's thickness lies across the ray: a slab spreads what it holds over its
  // thickness, which must stay within a pixel (near the limb, 2 km slabs under pixels 2.3 km wide
  // drew the storm's top a slab higher: 7 % more opacity than the march, against 2-5 % with
  // pixels twice as wide).
  const double sinIncidence = std::sin(glm::radians(std::min(90.0, plan.view.maxIncidenceDeg)));
  if (plan.view.rect && thickest * sinIncidence > kMaxSlabAcrossPixels * footprint) return {};
  // Seen slantwise, a ray's piece of a slab may also run more than a pixel sideways (near the limb
  // tens of km): cut into sub-pieces then.
  plan.view.subPieces = plan.view.maxIncidenceDeg >= 89.0 ||
                        thickest * std::tan(glm::radians(plan.view.maxIncidenceDeg)) > footprint;
  return plan;
}

std::vector<double> FarFieldGL::settingsKey(const VolumeLayerGL& layer) {
  const VolumeRenderOptions& o = layer.options;
  const volume::VolumeRenderSettings& r = o.render;
  std::vector<double> key{r.stepMeters, r.earlyTerminationAlpha, double(r.interpolation), double(o.classification),
                          double(o.skipEmptySpace)};
  appendTransferKey(r.transfer, key);
  return key;
}

void FarFieldGL::release(Slabs& s) {
  for (unsigned int t : {s.texture, s.mask})
    if (t) glDeleteTextures(1, &t);
  s = Slabs{};
}

void FarFieldGL::beginFrame(double budgetMs) {
  ++frame_;
  budgetMs_ = budgetMs;
  spentMs_ = 0.0;
  bandsThisFrame_ = 0;
  pending_ = false;
}

bool FarFieldGL::prepare(VolumeRendererGL& marcher, const VolumeLayerGL& layer, const FarFieldPlan& plan) {
  const std::vector<double> settings = settingsKey(layer);
  const std::uint64_t id = layer.volume->id();
  auto it = findKept(id);
  // The most recently used last.
  if (it != kept_.end()) {
    std::rotate(it, it + 1, kept_.end());
  } else {
    // Room for kKeptVolumes volumes (a national network's clusters): the least recently used not
    // drawn in this frame goes; more in one frame than that are marched.
    if (kept_.size() >= kKeptVolumes && !evictOne()) return false;
    kept_.push_back({});
    kept_.back().volumeId = id;
  }
  Kept& k = kept_.back();
  k.usedInFrame = frame_;
  // Slabs of this volume's field as it is now (the same settings, slabs and grid corner)...
  const auto sameField = [&](const Slabs& s) {
    return s.texture && s.uniformVersion == layer.volume->uniformVersion() && s.settings == settings &&
           s.plan.boundariesMeters == plan.boundariesMeters && s.plan.westDeg == plan.westDeg &&
           s.plan.southDeg == plan.southDeg;
  };
  // ...as fine as the plan's or finer serve it (a view moving away makes none).
  const auto serves = [&](const Slabs& s) {
    return sameField(s) && s.plan.latStepDeg <= plan.latStepDeg && s.plan.lonStepDeg <= plan.lonStepDeg;
  };
  if (serves(k.ready)) {
    release(k.building);  // finer slabs begun for a nearer view: not finished, not kept
    return true;
  }
  if (!serves(k.building)) {
    release(k.building);
    const std::vector<FarFieldLevel> levels = levelsOf(plan.boundariesMeters);
    Slabs s;
    s.layers = levels.back().slabs.front().layer + 1;  // the whole column's merged slab is the last layer
    s.texture = makeVolumeTextureGL(GL_TEXTURE_2D_ARRAY, GL_LINEAR);
    clearErrorsGL();
    glTextureStorage3D(s.texture, 1, GL_RGBA16F, plan.columns, plan.rows, s.layers);
    if (outOfMemoryGL()) {
      release(s);
      return sameField(k.ready);
    }
    // Columns the march leaves (outside every radar) stay clear.
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearTexImage(s.texture, 0, GL_RGBA, GL_FLOAT, zero);
    s.uniformVersion = layer.volume->uniformVersion();
    s.settings = settings;
    s.plan = plan;
    k.building = std::move(s);
  }
  if (!build(marcher, layer, k.building)) {
    release(k.building);
    return false;
  }
  if (k.building.slabsDone < k.building.plan.slabCount()) {
    pending_ = true;
    return sameField(k.ready);  // coarser slabs meanwhile, or the march
  }
  // The merged slabs, then the mask (a pass over the slabs in bands of rows with a budget, and a
  // read-back), counted in the frame's budget.
  if (!makeMerged(k.building) || !makeMask(k.building)) {
    pending_ = true;
    return sameField(k.ready);
  }
  release(k.ready);
  k.ready = std::move(k.building);
  k.building = Slabs{};
  ++made_;
  // Within kMaxKeptBytes: the least recently used others go, never one drawn in this frame (its
  // slabs would be made again next frame, and the next completed set would take another's).
  while (gpuBytes() > kMaxKeptBytes && evictOne()) {
  }
  return true;
}

std::vector<FarFieldGL::Kept>::iterator FarFieldGL::findKept(std::uint64_t volumeId) {
  return std::find_if(kept_.begin(), kept_.end(), [&](const Kept& k) { return k.volumeId == volumeId; });
}

bool FarFieldGL::evictOne() {
  for (auto it = kept_.begin(); it != kept_.end(); ++it) {
    if (it->usedInFrame == frame_) continue;
    release(it->ready);
    release(it->building);
    kept_.erase(it);
    return true;
  }
  return false;
}

bool FarFieldGL::build(VolumeRendererGL& marcher, const VolumeLayerGL& layer, Slabs& s) {
  const FarFieldPlan& plan = s.plan;
  const int slabs = plan.slabCount();
  const bool bounded = budgetMs_ > 0.0;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, plan.columns, plan.rows);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glEnable(GL_SCISSOR_TEST);
  // Bands are timed alone: what the frame queued before (the globe, other passes) finished first.
  if (bounded) glFinish();
  bool ok = true;
  while (ok && s.slabsDone < slabs) {
    // With a budget: at least one band a frame, then while time is left.
    if (bounded && bandsThisFrame_ > 0 && spentMs_ >= budgetMs_) break;
    // A band: whole rows (the rest of the slab) without a budget; with one, one or two blocks of
    // kBandBlock x kBandBlock texels along the current block row, as many as the time left allows
    // at each block's predicted cost: the same block's in the slab before, else the last band's.
    // (A band grown from the last band's cost alone ran to 40-150 ms where it reached storms.)
    const int left = plan.rows - s.rowsDone;
    const int blockRows = std::min(kBandBlock, left);
    int x = 0, width = plan.columns, rows = left;
    const int blocksAcross = (plan.columns + kBandBlock - 1) / kBandBlock;
    const int blockRow = s.rowsDone / kBandBlock;
    if (bounded) {
      const double timeLeftMs = budgetMs_ - spentMs_;
      double predictedMs = 0.0;
      int blocks = 0;
      // Until a band's cost is known, one block.
      const int most = msPerTexel_ > 0.0 ? kMaxBandBlocks : 1;
      for (int b = s.columnsDone / kBandBlock; b < blocksAcross && blocks < most; ++b) {
        const double before = s.costBefore.empty() ? 0.0 : s.costBefore[std::size_t(blockRow) * blocksAcross + b];
        const double texels = double(std::min(kBandBlock, plan.columns - b * kBandBlock)) * blockRows;
        const double ms = (before > 0.0 ? before : msPerTexel_) * texels;
        if (blocks > 0 && predictedMs + ms > timeLeftMs) break;
        predictedMs += ms;
        ++blocks;
      }
      // Not even one block fits what is left (at least one band a frame): the next frame.
      if (bandsThisFrame_ > 0 && predictedMs > timeLeftMs) break;
      x = s.columnsDone;
      width = std::min(plan.columns - x, blocks * kBandBlock);
      rows = blockRows;
    }
    glNamedFramebufferTextureLayer(fbo_, GL_COLOR_ATTACHMENT0, s.texture, 0, s.slabsDone);
    glScissor(x, s.rowsDone, width, rows);
    const auto start = std::chrono::steady_clock::now();
    ok = marcher.marchColumns(layer, plan, s.slabsDone);
    if (bounded) {
      glFinish();  // the time taken, not the time to queue
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      spentMs_ += ms;
      msPerTexel_ = ms / (static_cast<double>(rows) * width);
      if (s.costNow.empty())
        s.costNow.assign(std::size_t(blocksAcross) * ((plan.rows + kBandBlock - 1) / kBandBlock), 0.0);
      for (int b = x / kBandBlock; b * kBandBlock < x + width; ++b)
        s.costNow[std::size_t(blockRow) * blocksAcross + b] = msPerTexel_;
    }
    ++bandsThisFrame_;
    ++bands_;
    if (x + width < plan.columns) {
      s.columnsDone = x + width;
      continue;
    }
    s.columnsDone = 0;
    s.rowsDone += rows;
    if (s.rowsDone == plan.rows) {
      ++s.slabsDone;
      s.rowsDone = 0;
      s.costBefore = std::move(s.costNow);
      s.costNow.clear();
    }
  }
  glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, 0, 0);  // so that a deleted texture is freed
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  return ok;
}

std::vector<FarFieldLevel> FarFieldGL::levelsOf(const std::vector<double>& boundariesMeters) {
  std::vector<FarFieldLevel> levels(1);
  for (std::size_t i = 0; i + 1 < boundariesMeters.size(); ++i)
    levels[0].slabs.push_back({static_cast<int>(i), boundariesMeters[i], boundariesMeters[i + 1]});
  int nextLayer = static_cast<int>(levels[0].slabs.size());
  while (levels.back().slabs.size() > 1) {
    const std::vector<FarFieldLevel::Slab>& below = levels.back().slabs;
    std::vector<FarFieldLevel::Slab> merged;
    // Pairs from the ground up (the slabs are listed from the top down).
    int i = static_cast<int>(below.size()) - 1;
    for (; i >= 1; i -= 2) {
      const FarFieldLevel::Slab& upper = below[std::size_t(i) - 1];
      const FarFieldLevel::Slab& lower = below[std::size_t(i)];
      merged.push_back({nextLayer++, upper.topMeters, lower.bottomMeters, upper.layer, lower.layer});
    }
    if (i == 0) merged.push_back({below[0].layer, below[0].topMeters, below[0].bottomMeters});
    std::reverse(merged.begin(), merged.end());
    levels.push_back({std::move(merged), 0.0});
  }
  for (FarFieldLevel& level : levels)
    for (const FarFieldLevel::Slab& slab : level.slabs)
      level.thickestMeters = std::max(level.thickestMeters, slab.topMeters - slab.bottomMeters);
  return levels;
}

bool FarFieldGL::makeMerged(Slabs& s) {
  std::vector<const FarFieldLevel::Slab*> merges;
  const std::vector<FarFieldLevel> levels = levelsOf(s.plan.boundariesMeters);
  for (const FarFieldLevel& level : levels)
    for (const FarFieldLevel::Slab& slab : level.slabs)
      if (slab.upperLayer >= 0) merges.push_back(&slab);
  if (s.mergesDone >= static_cast<int>(merges.size())) return true;
  const bool bounded = budgetMs_ > 0.0;
  if (bounded) glFinish();  // timed alone
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, s.plan.columns, s.plan.rows);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  mergeProgram_.use();
  glUniform1i(mergeProgram_.uniform("u_slabs"), 0);
  glBindTextureUnit(0, s.texture);
  glBindVertexArray(vao_);
  // Merged slabs are listed level by level: each reads layers made before it.
  while (s.mergesDone < static_cast<int>(merges.size())) {
    if (bounded && bandsThisFrame_ > 0 && spentMs_ >= budgetMs_) break;
    const FarFieldLevel::Slab& m = *merges[std::size_t(s.mergesDone)];
    const auto start = std::chrono::steady_clock::now();
    glNamedFramebufferTextureLayer(fbo_, GL_COLOR_ATTACHMENT0, s.texture, 0, m.layer);
    glUniform1i(mergeProgram_.uniform("u_upper"), m.upperLayer);
    glUniform1i(mergeProgram_.uniform("u_lower"), m.lowerLayer);
    // The pass reads two layers of the texture it writes a third of: disjoint texels, defined; a
    // layer written by an earlier merge is read only after a texture barrier (GL 4.5, 9.3.1).
    glTextureBarrier();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    if (bounded) {
      glFinish();
      spentMs_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    ++s.mergesDone;
    ++bandsThisFrame_;
    ++bands_;
  }
  glBindVertexArray(0);
  glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, 0, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glEnable(GL_DEPTH_TEST);
  return s.mergesDone >= static_cast<int>(merges.size());
}

std::vector<std::vector<std::uint8_t>> FarFieldGL::maskPyramid(std::vector<std::uint8_t> level0, int width,
                                                               int height) {
  std::vector<std::vector<std::uint8_t>> levels;
  levels.push_back(std::move(level0));
  int bw = width, bh = height;
  for (int l = 1; l < maskLevelCount(width, height); ++l) {
    const std::vector<std::uint8_t>& below = levels.back();
    const int lw = std::max(1, width >> l), lh = std::max(1, height >> l);
    std::vector<std::uint8_t> level(static_cast<std::size_t>(lw) * static_cast<std::size_t>(lh), 0);
    for (int j = 0; j < lh; ++j) {
      const int y1 = j == lh - 1 ? bh - 1 : 2 * j + 1;
      for (int i = 0; i < lw; ++i) {
        const int x1 = i == lw - 1 ? bw - 1 : 2 * i + 1;
        std::uint8_t m = 0;
        for (int y = 2 * j; y <= y1; ++y)
          for (int x = 2 * i; x <= x1; ++x)
            m = std::max(
                m, below[static_cast<std::size_t>(y) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(x)]);
        level[static_cast<std::size_t>(j) * static_cast<std::size_t>(lw) + static_cast<std::size_t>(i)] = m;
      }
    }
    levels.push_back(std::move(level));
    bw = lw;
    bh = lh;
  }
  return levels;
}

FarFieldGL::MaskAtlas FarFieldGL::maskAtlas(int width, int height) {
  MaskAtlas atlas;
  atlas.levels.push_back({0, 0, width, height});
  // Past the shorter side, along the longer one: level l's side there is max(1, side >> l), and
  // levels go down to 1 x 1 where the longer side ends, so they sum to less than it.
  const bool wide = width >= height;
  int along = 0;
  for (int l = 1; l < maskLevelCount(width, height); ++l) {
    const int lw = std::max(1, width >> l), lh = std::max(1, height >> l);
    atlas.levels.push_back(wide ? std::array<int, 4>{along, height, lw, lh} : std::array<int, 4>{width, along, lw, lh});
    along += wide ? lw : lh;
  }
  const int across = atlas.levels.size() > 1 ? (wide ? atlas.levels[1][3] : atlas.levels[1][2]) : 0;
  atlas.width = wide ? std::max(width, along) : width + across;
  atlas.height = wide ? height + across : std::max(height, along);
  return atlas;
}

bool FarFieldGL::makeMask(Slabs& s) {
  const int w = s.plan.columns, h = s.plan.rows;
  if (s.maskFailed) return true;
  if (!s.mask) {
    const MaskAtlas atlas = maskAtlas(w, h);
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    if (atlas.width > maxSize || atlas.height > maxSize ||
        atlas.levels.size() > static_cast<std::size_t>(kMaxMaskLevels)) {  // no mask: every pixel visits the slabs
      s.maskFailed = true;
      return true;
    }
    s.mask = makeVolumeTextureGL(GL_TEXTURE_2D, GL_NEAREST);
    clearErrorsGL();
    glTextureStorage2D(s.mask, 1, GL_R8, atlas.width, atlas.height);
    if (outOfMemoryGL()) {
      glDeleteTextures(1, &s.mask);
      s.mask = 0;
      s.maskFailed = true;
      return true;
    }
  }
  // Level 0 from the slabs: whole without a budget, else bands of kBandBlock rows while the
  // frame's time lasts (at least one band a frame; 2078 x 1008 texels took about 130 ms at once).
  const bool bounded = budgetMs_ > 0.0;
  if (bounded) glFinish();  // bands are timed alone
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, s.mask, 0);
  glViewport(0, 0, w, h);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glEnable(GL_SCISSOR_TEST);
  maskProgram_.use();
  glUniform1i(maskProgram_.uniform("u_slabCount"), s.plan.slabCount());
  glUniform1i(maskProgram_.uniform("u_slabs"), 0);
  glBindTextureUnit(0, s.texture);
  glBindVertexArray(vao_);
  while (s.maskRowsDone < h) {
    if (bounded && bandsThisFrame_ > 0 && spentMs_ >= budgetMs_) break;
    const int rows = bounded ? std::min(kBandBlock, h - s.maskRowsDone) : h - s.maskRowsDone;
    const auto start = std::chrono::steady_clock::now();
    glScissor(0, s.maskRowsDone, w, rows);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    if (bounded) {
      glFinish();
      spentMs_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    s.maskRowsDone += rows;
    ++bandsThisFrame_;
    ++bands_;
  }
  glBindVertexArray(0);
  glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, 0, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  if (s.maskRowsDone < h) return false;
  // The coarser levels: each texel the largest of those it covers.
  const auto start = std::chrono::steady_clock::now();
  GLint packAlignment = 4, unpackAlignment = 4;
  glGetIntegerv(GL_PACK_ALIGNMENT, &packAlignment);
  glGetIntegerv(GL_UNPACK_ALIGNMENT, &unpackAlignment);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  std::vector<std::uint8_t> below(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  glGetTextureSubImage(s.mask, 0, 0, 0, 0, w, h, 1, GL_RED, GL_UNSIGNED_BYTE, static_cast<GLsizei>(below.size()),
                       below.data());
  const std::vector<std::vector<std::uint8_t>> pyramid = maskPyramid(std::move(below), w, h);
  const MaskAtlas atlas = maskAtlas(w, h);
  for (std::size_t l = 1; l < pyramid.size(); ++l) {
    const std::array<int, 4>& r = atlas.levels[l];
    glTextureSubImage2D(s.mask, 0, r[0], r[1], r[2], r[3], GL_RED, GL_UNSIGNED_BYTE, pyramid[l].data());
  }
  glPixelStorei(GL_PACK_ALIGNMENT, packAlignment);
  glPixelStorei(GL_UNPACK_ALIGNMENT, unpackAlignment);
  if (bounded) spentMs_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return true;
}

FarFieldGL::BoxView FarFieldGL::viewOf(const Camera& camera, const FarFieldPlan& plan) {
  // A grid of points over the texel grid's box at the ground and at the top: the rectangle of
  // those the eye sees (in front, not behind the Earth), widened by the largest step between
  // neighbouring points on the screen, so that what lies between them is inside; and the largest
  // angle between the eye's direction and the vertical at the ground points it sees.
  constexpr int kN = 16;
  BoxView view;
  glm::dvec2 lo(1e300), hi(-1e300);
  double spacing = 0.0;
  const double heights[2] = {0.0, plan.boundariesMeters.front()};
  for (double h : heights) {
    std::vector<std::optional<glm::dvec2>> row(kN + 1), previous(kN + 1);
    for (int j = 0; j <= kN; ++j) {
      for (int i = 0; i <= kN; ++i) {
        const double lat = std::min(90.0, plan.southDeg + plan.rows * plan.latStepDeg * j / kN);
        const double lon = plan.westDeg + plan.columns * plan.lonStepDeg * i / kN;
        const glm::dvec3 p = globe::geodeticToEcef({lat, lon, h});
        std::optional<glm::dvec2> px = camera.projectToPixel(p);
        // A point behind the eye: the box crosses the image plane, whose edges it may reach anywhere.
        if (!px) {
          view.rect = glm::dvec4(-1e8, -1e8, 1e8, 1e8);
          view.maxIncidenceDeg = 90.0;
          return view;
        }
        // Behind the Earth: the ray from the eye meets the ellipsoid well before the point.
        const glm::dvec3 d = p - camera.eyeEcef();
        const double dist = glm::length(d);
        if (auto hit = globe::intersectRayEllipsoid(camera.eyeEcef(), d / dist))
          if (glm::length(*hit - camera.eyeEcef()) < dist - 1000.0) px.reset();
        row[static_cast<std::size_t>(i)] = px;
        if (!px) continue;
        if (h == 0.0) {
          const double cosIncidence = glm::dot(-d / dist, globe::surfaceNormal(lat, lon));
          view.maxIncidenceDeg =
              std::max(view.maxIncidenceDeg, glm::degrees(std::acos(std::clamp(cosIncidence, -1.0, 1.0))));
        }
        lo = glm::min(lo, *px);
        hi = glm::max(hi, *px);
        if (i > 0 && row[static_cast<std::size_t>(i) - 1])
          spacing = std::max(spacing, glm::length(*px - *row[static_cast<std::size_t>(i) - 1]));
        if (j > 0 && previous[static_cast<std::size_t>(i)])
          spacing = std::max(spacing, glm::length(*px - *previous[static_cast<std::size_t>(i)]));
      }
      previous = row;
    }
  }
  if (lo.x > hi.x) return view;
  // Clamped: points just in front of the image plane project far outside it.
  view.rect = glm::clamp(glm::dvec4(lo - spacing - 2.0, hi + spacing + 2.0), -1e8, 1e8);
  return view;
}

void FarFieldGL::draw(const Camera& camera, const VolumeLayerGL& layer, const FarFieldPlan::View& view,
                      unsigned int depthTexture) {
  if (!view.rect) return;
  const glm::dvec4& rectPx = *view.rect;
  auto kept = findKept(layer.volume->id());
  if (kept == kept_.end() || !kept->ready.texture) return;
  const Slabs* s = &kept->ready;
  const FarFieldPlan& plan = s->plan;
  // Only the pixels that can see it (a cluster's pass may span the image).
  GLint viewport[4], scissor[4];
  glGetIntegerv(GL_VIEWPORT, viewport);
  glGetIntegerv(GL_SCISSOR_BOX, scissor);
  const double sx = viewport[2] / static_cast<double>(camera.widthPx());
  const double sy = viewport[3] / static_cast<double>(camera.heightPx());
  // Pixel rows from the top -> GL rows from the bottom, in the bound image's pixels.
  const int x0 = std::max(scissor[0], static_cast<int>(std::floor(rectPx.x * sx)));
  const int x1 = std::min(scissor[0] + scissor[2], static_cast<int>(std::ceil(rectPx.z * sx)));
  const int y0 = std::max(scissor[1], static_cast<int>(std::floor(viewport[3] - rectPx.w * sy)));
  const int y1 = std::min(scissor[1] + scissor[3], static_cast<int>(std::ceil(viewport[3] - rectPx.y * sy)));
  if (x1 <= x0 || y1 <= y0) return;
  glScissor(x0, y0, x1 - x0, y1 - y0);
  ShaderProgramGL& program = view.subPieces ? subPiecesProgram_ : program_;
  program.use();
  const glm::mat3 cameraToEcef(camera.cameraToEcef());
  glUniformMatrix3fv(program.uniform("u_cameraToEcef"), 1, GL_FALSE, glm::value_ptr(cameraToEcef));
  glUniform1f(program.uniform("u_focalPx"), static_cast<float>(camera.focalLengthPx()));
  glUniform2f(program.uniform("u_imageSizePx"), static_cast<float>(camera.widthPx()),
              static_cast<float>(camera.heightPx()));
  glUniform1f(program.uniform("u_near"), static_cast<float>(camera.nearMeters()));
  const glm::vec3 eye(camera.eyeEcef());
  glUniform3fv(program.uniform("u_eyeEcef"), 1, glm::value_ptr(eye));
  glUniform4f(program.uniform("u_box"), static_cast<float>(plan.westDeg), static_cast<float>(plan.southDeg),
              static_cast<float>(plan.lonStepDeg), static_cast<float>(plan.latStepDeg));
  glUniform2f(program.uniform("u_texels"), static_cast<float>(plan.columns), static_cast<float>(plan.rows));
  const int slabs = plan.slabCount();
  glUniform1i(program.uniform("u_slabCount"), slabs);
  std::vector<float> heights(plan.boundariesMeters.begin(), plan.boundariesMeters.end());
  glUniform1fv(program.uniform("u_heights"), static_cast<GLsizei>(heights.size()), heights.data());
  // The levels of merged slabs: per level its first slab, count and thickest slab; per slab its
  // layer and its top and bottom heights.
  const std::vector<FarFieldLevel> levels = levelsOf(plan.boundariesMeters);
  const int levelCount = mergedLevels_ ? static_cast<int>(levels.size()) : 1;
  std::vector<GLint> levelFirst, levelSlabs, layers;
  std::vector<float> thickest, tops, bottoms;
  for (int l = 0; l < levelCount; ++l) {
    levelFirst.push_back(static_cast<GLint>(layers.size()));
    levelSlabs.push_back(static_cast<GLint>(levels[std::size_t(l)].slabs.size()));
    thickest.push_back(static_cast<float>(levels[std::size_t(l)].thickestMeters));
    for (const FarFieldLevel::Slab& slab : levels[std::size_t(l)].slabs) {
      layers.push_back(slab.layer);
      tops.push_back(static_cast<float>(slab.topMeters));
      bottoms.push_back(static_cast<float>(slab.bottomMeters));
    }
  }
  glUniform1i(program.uniform("u_levelCount"), levelCount);
  glUniform1iv(program.uniform("u_levelFirst"), levelCount, levelFirst.data());
  glUniform1iv(program.uniform("u_levelSlabs"), levelCount, levelSlabs.data());
  glUniform1fv(program.uniform("u_levelThickest"), levelCount, thickest.data());
  const GLsizei entries = static_cast<GLsizei>(layers.size());
  glUniform1iv(program.uniform("u_slabLayer"), entries, layers.data());
  glUniform1fv(program.uniform("u_slabTop"), entries, tops.data());
  glUniform1fv(program.uniform("u_slabBottom"), entries, bottoms.data());
  glBindTextureUnit(0, s->texture);
  glBindTextureUnit(1, depthTexture);
  glBindTextureUnit(2, s->mask);
  glUniform1i(program.uniform("u_slabs"), 0);
  glUniform1i(program.uniform("u_globeDepth"), 1);
  glUniform1i(program.uniform("u_mask"), 2);
  glUniform1i(program.uniform("u_hasMask"), s->mask != 0 && maskSkipping_ ? 1 : 0);
  if (s->mask) {
    const MaskAtlas atlas = maskAtlas(s->plan.columns, s->plan.rows);
    std::vector<GLint> regions;
    for (const std::array<int, 4>& r : atlas.levels) regions.insert(regions.end(), r.begin(), r.end());
    glUniform1i(program.uniform("u_maskLevels"), static_cast<GLint>(atlas.levels.size()));
    glUniform4iv(program.uniform("u_maskLevel"), static_cast<GLsizei>(atlas.levels.size()), regions.data());
  }
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glScissor(scissor[0], scissor[1], scissor[2], scissor[3]);
}

std::size_t FarFieldGL::gpuBytes() const {
  std::size_t bytes = 0;
  for (const Kept& k : kept_)
    for (const Slabs* s : {&k.ready, &k.building})
      if (s->texture) {
        const std::size_t texels = static_cast<std::size_t>(s->plan.columns) * static_cast<std::size_t>(s->plan.rows);
        bytes += texels * static_cast<std::size_t>(s->layers) * 8;
        if (s->mask) {  // R8, every level in one
          const MaskAtlas atlas = maskAtlas(s->plan.columns, s->plan.rows);
          bytes += static_cast<std::size_t>(atlas.width) * static_cast<std::size_t>(atlas.height);
        }
      }
  return bytes;
}

}  // namespace atmoglobe::engine
