#include <atmoglobe/engine/SceneRendererGL.h>

#include <atmoglobe/globe/ImageryPyramid.h>
#include <atmoglobe/globe/XyzLayer.h>

#include <chrono>

namespace atmoglobe::engine {

Result<std::shared_ptr<globe::TileImageLoader>> openImagery(const std::vector<ImageryLayerDescription>& layers,
                                                           const globe::TileImageLoaderOptions& options) {
  std::vector<std::shared_ptr<const globe::ImageryLayer>> opened;
  for (const ImageryLayerDescription& d : layers) {
    if (d.type == ImageryLayerDescription::Type::Pyramid) {
      auto layer = globe::GeographicPyramidLayer::open(d.path);
      if (!layer) return makeError(layer.error());
      opened.push_back(*layer);
    } else {
      auto layer = globe::XyzMercatorLayer::open(d.path);
      if (!layer) return makeError(layer.error());
      opened.push_back(*layer);
    }
  }
  return std::make_shared<globe::TileImageLoader>(std::move(opened), options);
}

Result<std::unique_ptr<SceneRendererGL>> SceneRendererGL::create(std::shared_ptr<globe::TileImageLoader> loader,
                                                                 const GlobeRenderOptions& globeOptions) {
  std::unique_ptr<SceneRendererGL> r(new SceneRendererGL());
  auto g = GlobeRendererGL::create(std::move(loader), globeOptions);
  if (!g) return makeError(g.error());
  r->globe_ = std::move(*g);
  auto m = MarkerRendererGL::create(MarkerStyle::Disc);
  if (!m) return makeError(m.error());
  r->markers_ = std::move(*m);
  return r;
}

SceneFrameStats SceneRendererGL::renderFrame(const Camera& camera, const std::vector<Marker>& markers) {
  const auto start = std::chrono::steady_clock::now();
  SceneFrameStats stats;
  // Reverse-Z: depth = near / distance in [0, 1]; 0 is infinitely far.
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glClearDepth(0.0);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_CULL_FACE);
  stats.globe = globe_->draw(camera);
  markers_->draw(camera, markers);
  stats.cpuMilliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

Result<globe::ImageRGBA8> SceneRendererGL::renderToImage(const Camera& camera, const std::vector<Marker>& markers,
                                                         FramebufferGL& target, int maxPasses,
                                                         SceneFrameStats* lastStats) {
  if (camera.widthPx() != target.widthPx() || camera.heightPx() != target.heightPx()) {
    return makeError("camera image size does not match the render target");
  }
  target.bind();
  SceneFrameStats stats;
  for (int pass = 0; pass < maxPasses; ++pass) {
    stats = renderFrame(camera, markers);
    if (globe_->lastFrameComplete()) break;
    globe_->loader().waitIdle();  // decoding happens on the loader's threads
  }
  glFinish();
  if (lastStats) *lastStats = stats;
  for (const std::string& e : globe_->loader().takeErrors()) {
    return makeError("imagery: " + e);
  }
  return target.readColor();
}

}  // namespace atmoglobe::engine
