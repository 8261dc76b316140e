#include <atmoglobe/engine/SceneRendererGL.h>

#include "LoaderGL.h"

#include <atmoglobe/engine/LayerEdit.h>
#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/ImageryPyramid.h>
#include <atmoglobe/globe/XyzLayer.h>
#include <atmoglobe/map/GeoLines.h>
#include <atmoglobe/volume/VerticalExaggeration.h>

#include <algorithm>
#include <chrono>
#include <utility>

namespace atmoglobe::engine {

Result<std::shared_ptr<globe::TileImageLoader>> openImagery(const std::vector<ImageryLayerDescription>& layers,
                                                            const globe::TileImageLoaderOptions& options) {
  std::vector<std::shared_ptr<const globe::ImageryLayer>> opened;
  for (const ImageryLayerDescription& d : layers) {
    if (d.type == ImageryLayerDescription::Type::Pyramid) {
      auto layer = globe::GeographicPyramidLayer::open(d.path);
      if (!layer) return layer.forwardError();
      opened.push_back(*layer);
    } else {
      auto layer = globe::XyzMercatorLayer::open(d.path);
      if (!layer) return layer.forwardError();
      opened.push_back(*layer);
    }
  }
  return std::make_shared<globe::TileImageLoader>(std::move(opened), options);
}

Result<std::unique_ptr<SceneRendererGL>> SceneRendererGL::create(std::shared_ptr<globe::TileImageLoader> loader,
                                                                 const GlobeRenderOptions& globeOptions) {
  std::unique_ptr<SceneRendererGL> r(new SceneRendererGL());
  auto g = GlobeRendererGL::create(std::move(loader), globeOptions);
  if (!g) return g.forwardError();
  r->globe_ = std::move(*g);
  auto m = MarkerRendererGL::create(MarkerStyle::Disc);
  if (!m) return m.forwardError();
  r->markers_ = std::move(*m);
  auto rv = VolumeRendererGL::create();
  if (!rv) return rv.forwardError();
  r->volumeRenderer_ = std::move(*rv);
  auto map = MapRendererGL::create(map::defaultGshhgDirectory());
  if (!map) return map.forwardError();
  r->map_ = std::move(*map);
  return r;
}

Status SceneRendererGL::setMapContext(bool enabled) {
  ++version_;
  return map_->setBuiltinLayers(enabled);
}

Result<std::string> SceneRendererGL::addOverlay(const MapOverlayDescription& d) {
  ++version_;
  return map_->addOverlay(d.path, MapLineStyle{d.color, d.widthPx, 1.0f});
}

Status SceneRendererGL::addModel(const std::string& glbPath) {
  ++version_;
  auto model = GltfModelRendererGL::load(glbPath);
  if (!model) return model.forwardError();
  models_.push_back(std::move(*model));
  return Ok{};
}

Status SceneRendererGL::setVerticalExaggeration(double factor) {
  ++version_;
  if (auto st = volume::validateVerticalExaggeration(factor, "scene"); !st) return st;
  if (volumeLayerCount() > 0 || (slices_ && slices_->size() > 0))
    return makeError("the vertical exaggeration must be set before volumes and slices are added");
  exaggeration_ = factor;
  return Ok{};
}

Result<std::string> SceneRendererGL::addSlice(const SliceLayerDescription& d) {
  ++version_;
  if (!slices_) {
    auto s = SliceRendererGL::create();
    if (!s) return s.forwardError();
    slices_ = std::move(*s);
  }
  slices_->setVerticalExaggeration(exaggeration_);
  return slices_->add(d);
}

Result<std::string> SceneRendererGL::addSurface(const SurfaceLayerDescription& d) {
  ++version_;
  auto data = readSurfaceData(d);
  if (!data) return data.forwardError();
  auto surface = SurfaceFieldGL::create(std::move(*data), d);
  if (!surface) return surface.forwardError();
  const SurfaceFieldGL& s = **surface;
  const volume::GridVolume& g = s.field().grid;
  std::string line = g.path + ": " + s.field().name + " [" + g.units + "] valid " + g.validTime + ", " +
                     std::to_string(g.nx) + " x " + std::to_string(g.ny) + " grid points, " +
                     std::to_string(s.contours().size()) + " contour lines";
  surfaces_.push_back(std::move(*surface));
  return line;
}

Result<VolumeSourceGL*> SceneRendererGL::addVolume(const VolumeLayerDescription& d) {
  auto source = openVolumeSource(d, contextFor(layers_.size()));
  if (!source) return source.forwardError();
  return &addSource(std::move(*source));
}

VolumeSourceGL& SceneRendererGL::addSource(std::unique_ptr<VolumeSourceGL> source) {
  ++version_;
  layers_.push_back(std::move(source));
  return *layers_.back();
}

Status SceneRendererGL::setLayerStep(std::size_t index, std::size_t step, double fraction) {
  ++version_;  // slices of its volumes
  if (index >= layers_.size()) return makeError("no volume layer " + std::to_string(index));
  return layers_[index]->showStep(step, fraction, contextFor(index));
}

namespace {
// Colour and depth of `from` into `to`, texel for texel (the same size and formats).
void copyColorAndDepthGL(const FramebufferGL& from, const FramebufferGL& to) {
  for (const auto& [src, dst] :
       {std::pair{from.colorTexture(), to.colorTexture()}, std::pair{from.depthTexture(), to.depthTexture()}})
    glCopyImageSubData(src, GL_TEXTURE_2D, 0, 0, 0, 0, dst, GL_TEXTURE_2D, 0, 0, 0, 0, to.widthPx(), to.heightPx(), 1);
}
}  // namespace

SceneFrameStats SceneRendererGL::renderFrame(const Camera& camera, const std::vector<Marker>& markers,
                                             const FramebufferGL& target) {
  const auto start = std::chrono::steady_clock::now();
  SceneFrameStats stats;
  volumesComplete_ = true;
  target.bind();
  // Reverse-Z: depth = near / distance in [0, 1]; 0 is infinitely far.
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glClearDepth(0.0);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glDisable(GL_CULL_FACE);
  // Range rings of layers added since the last frame change the map: drawn, not reused.
  const bool ringsPending = rangeRings_ && layersWithRings_ < layers_.size();
  if (backgroundReuse_ && !ringsPending && backgroundMatches(camera, target)) {
    // Nothing but the volumes changed (the caller's word) and the camera is the same: the
    // background kept from the last refining frame, colour and depth (the march reads the depth).
    copyColorAndDepthGL(*background_.image, target);
    stats.globe = background_.globe;
    stats.globe.meshesBuilt = stats.globe.texturesUploaded = 0;  // nothing built or uploaded this frame
    stats.map = background_.map;
    stats.map.chunksBuilt = 0;
    ++backgroundsReused_;
  } else {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    stats.globe = globe_->draw(camera);
    for (const auto& model : models_) model->draw(camera);
    if (slices_) slices_->draw(camera);  // before the volumes: the march stops at their depth
    for (const auto& surface : surfaces_)
      if (surface->visible) surface->drawFill(camera);  // no depth written: under the volumes
    for (; rangeRings_ && layersWithRings_ < layers_.size(); ++layersWithRings_) {
      if (auto rings = layers_[layersWithRings_]->rangeRings(); !rings.empty())
        map_->addLines(rings, MapLineStyle{glm::vec3(0.95f, 0.9f, 0.55f), 1.0f, 0.7f});
    }
    stats.map = map_->draw(camera);  // writes no depth: the march sees the globe's
    for (const auto& surface : surfaces_)
      if (surface->visible) surface->drawContours(camera);
    // Kept for the frames that follow while the volumes refine, once nothing is still loading.
    background_.valid = false;
    if (progressiveBudgetMs_ > 0.0 && globe_->lastFrameComplete() && map_->lastFrameComplete())
      keepBackground(camera, target, stats);
  }
  target.bind();
  // Every volume in one draw: where volumes overlap, the march integrates them together.
  std::vector<Marker> all = markers;
  for (const auto& surface : surfaces_)
    if (surface->visible) all.insert(all.end(), surface->contourLabels().begin(), surface->contourLabels().end());
  std::vector<VolumeLayerGL> layers;
  for (std::size_t i : volumeOrder()) {  // the panel's order; layers switched off are left out
    VolumeSourceGL& source = *layers_[i];
    if (!source.visible) continue;
    source.chooseDetail(camera, detailInBackground_);  // a grid's level of detail for this camera
    for (const VolumeGL* v : source.volumes()) layers.push_back(VolumeLayerGL{v, source.options(), source.holeOf(v)});
    for (const Marker& site : source.siteMarkers()) all.push_back(site);
  }
  if (!layers.empty() && referenceThreads_ > 0) {
    const auto t0 = std::chrono::steady_clock::now();
    volumeRenderer_->drawReference(camera, layers, target, referenceThreads_);
    stats.referenceSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } else if (!layers.empty() && progressiveBudgetMs_ > 0.0) {
    volumesComplete_ = volumeRenderer_->drawProgressive(camera, layers, target, progressiveBudgetMs_) &&
                       !volumeRenderer_->farFieldPending();
  } else if (!layers.empty()) {
    volumeRenderer_->draw(camera, layers, target);
    volumesComplete_ = !volumeRenderer_->farFieldPending();  // slabs made over frames (viewer)
  }
  if (exaggeration_ != 1.0)
    for (Marker& m : all) m.heightMeters *= exaggeration_;
  markers_->draw(camera, all);
  stats.cpuMilliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

bool SceneRendererGL::backgroundMatches(const Camera& camera, const FramebufferGL& target) const {
  const KeptBackground& b = background_;
  if (!b.valid || !b.image || b.version != version_ || b.fovYDeg != camera.fovYDeg()) return false;
  if (b.image->widthPx() != target.widthPx() || b.image->heightPx() != target.heightPx()) return false;
  GLint format = 0;  // glCopyImageSubData copies texels as they are: the same format only
  glGetTextureLevelParameteriv(target.colorTexture(), 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
  if (format != b.colorFormat) return false;
  const CameraPose& p = camera.pose();
  return b.pose.latDeg == p.latDeg && b.pose.lonDeg == p.lonDeg && b.pose.heightMeters == p.heightMeters &&
         b.pose.headingDeg == p.headingDeg && b.pose.pitchDeg == p.pitchDeg && b.pose.rollDeg == p.rollDeg;
}

void SceneRendererGL::keepBackground(const Camera& camera, const FramebufferGL& target, const SceneFrameStats& stats) {
  KeptBackground& b = background_;
  // The same sized formats as the target's (glCopyImageSubData copies texels as they are).
  GLint format = 0;
  glGetTextureLevelParameteriv(target.colorTexture(), 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
  if (!b.image || b.image->widthPx() != target.widthPx() || b.image->heightPx() != target.heightPx() ||
      b.colorFormat != format) {
    b.image.reset();
    b.colorFormat = format;
    auto made = FramebufferGL::create(target.widthPx(), target.heightPx(), static_cast<unsigned int>(format));
    if (!made) return;  // no memory for it: every frame draws its background
    b.image = std::move(*made);
  }
  copyColorAndDepthGL(target, *b.image);
  b.pose = camera.pose();
  b.fovYDeg = camera.fovYDeg();
  b.version = version_;
  b.globe = stats.globe;
  b.map = stats.map;
  b.valid = true;
}

Result<globe::ImageRGBA8> SceneRendererGL::renderToImage(const Camera& camera, const std::vector<Marker>& markers,
                                                         FramebufferGL& target, int maxPasses,
                                                         SceneFrameStats* lastStats) {
  if (camera.widthPx() != target.widthPx() || camera.heightPx() != target.heightPx()) {
    return makeError("camera image size does not match the render target");
  }
  SceneFrameStats stats;
  // Bring the imagery in with globe-only passes (cheap), then draw the whole frame once.
  for (int pass = 0; pass < maxPasses; ++pass) {
    target.bind();
    stats.globe = globe_->draw(camera);
    if (globe_->lastFrameComplete()) break;
    globe_->loader().waitIdle();  // decoding happens on the loader's threads
  }
  stats = renderFrame(camera, markers, target);
  glFinish();
  if (lastStats) *lastStats = stats;
  for (const std::string& e : globe_->loader().takeErrors()) {
    return makeError("imagery: " + e);
  }
  return target.readColor();
}

FrameLegend SceneRendererGL::legendFor(const Camera& camera) const {
  FrameLegend legend;
  std::string what;
  auto add = [&](const std::string& s) { what += (what.empty() ? "" : "  |  ") + s; };
  for (const auto& source : layers_) {
    if (!source->visible) continue;
    LegendPart part = source->legendPart();
    add(part.title);
    legend.subtitles.push_back(std::move(part.subtitle));
    legend.keys.push_back(std::move(part.key));
    legend.synthetic = legend.synthetic || part.synthetic;
  }
  for (const auto& surface : surfaces_) {
    if (!surface->visible) continue;
    add(surface->title());
    legend.subtitles.push_back(surface->subtitle());
    if (auto key = surface->key()) legend.keys.push_back(std::move(*key));
  }
  legend.title = what;
  if (exaggeration_ != 1.0) legend.subtitles.push_back("vertical exaggeration x" + fixed(exaggeration_, 1));
  // Scale at the image centre: the ground distance one pixel spans there.
  const glm::dvec3 dir = camera.pixelRayDirection(0.5 * camera.widthPx(), 0.5 * camera.heightPx());
  if (auto hit = globe::intersectRayEllipsoid(camera.eyeEcef(), dir)) {
    legend.metersPerPixel = glm::length(*hit - camera.eyeEcef()) / camera.focalLengthPx();
  }
  return legend;
}

// --- Live edits (the control panel) ---

const VolumeLayerDescription& SceneRendererGL::volumeDescription(std::size_t index) const {
  return layers_.at(index)->description();
}

Status SceneRendererGL::setVolumeDescription(std::size_t index, const VolumeLayerDescription& d) {
  ++version_;
  if (index >= volumeLayerCount()) return makeError("no volume layer " + std::to_string(index));
  if (d.kind != volumeDescription(index).kind)
    return makeError(d.path + ": a " + nameOf(volumeDescription(index).kind) + " layer cannot become a " +
                     nameOf(d.kind));
  if (auto st = validateVolumeLayer(d, d.path); !st) return st;
  return layers_[index]->setDescription(d, contextFor(index));
}

Status SceneRendererGL::setSurfaceDescription(std::size_t index, const SurfaceLayerDescription& d) {
  ++version_;
  if (index >= surfaces_.size()) return makeError("no surface layer " + std::to_string(index));
  if (auto st = validateSurfaceLayer(d, d.path); !st) return st;
  const SurfaceFieldGL& now = *surfaces_[index];
  Result<SurfaceData> data = sameSurfaceData(now.description(), d) ? Result<SurfaceData>(now.data())
                                                                   : readSurfaceData(d);
  if (!data) return data.forwardError();
  auto surface = SurfaceFieldGL::create(std::move(*data), d);
  if (!surface) return surface.forwardError();
  (*surface)->visible = now.visible;
  surfaces_[index] = std::move(*surface);
  return Ok{};
}

void SceneRendererGL::setSurfaceVisible(std::size_t index, bool visible) {
  ++version_;
  if (index < surfaces_.size()) surfaces_[index]->visible = visible;
}

Status SceneRendererGL::changeVerticalExaggeration(double factor) {
  ++version_;
  if (auto st = volume::validateVerticalExaggeration(factor, "scene"); !st) return st;
  if (factor == exaggeration_) return Ok{};
  if (slices_ && slices_->size() > 0)
    return makeError("the scene has slices: its vertical exaggeration is fixed when they are sampled");
  const double previous = exaggeration_;
  exaggeration_ = factor;
  for (std::size_t i = 0; i < layers_.size(); ++i) {
    if (auto st = layers_[i]->applyExaggeration(contextFor(i)); !st) {
      exaggeration_ = previous;  // the layers changed so far go back (from their CPU copies or files)
      for (std::size_t k = 0; k < i; ++k) (void)layers_[k]->applyExaggeration(contextFor(k));
      return st;
    }
  }
  return Ok{};
}

Status SceneRendererGL::setVolumeOrder(const std::vector<std::size_t>& order) {
  ++version_;
  std::vector<std::size_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i)
    if (sorted[i] != i) return makeError("the volume order is not a permutation of the layers");
  if (sorted.size() != volumeLayerCount()) return makeError("the volume order must name every layer once");
  volumeOrder_ = order;
  return Ok{};
}

std::vector<std::size_t> SceneRendererGL::volumeOrder() const {
  // The order set, then the layers added since in the order added.
  std::vector<std::size_t> order = volumeOrder_;
  for (std::size_t i = volumeOrder_.size(); i < volumeLayerCount(); ++i) order.push_back(i);
  return order;
}

std::vector<LayerMemory> SceneRendererGL::layerMemory() const {
  std::vector<LayerMemory> out;
  for (const auto& source : layers_) out.push_back(source->memory());
  return out;
}

}  // namespace atmoglobe::engine
