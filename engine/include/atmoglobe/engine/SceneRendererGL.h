#pragma once
// Renders a SceneDescription: globe, then markers, with reverse-Z depth. The render loop
// for headless images waits until every tile has the imagery it wants.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/GlobeRendererGL.h>
#include <atmoglobe/engine/MarkerRendererGL.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/TileImageLoader.h>

#include <memory>

namespace atmoglobe::engine {

/// Opens the scene's imagery layers (bottom first) behind one asynchronous loader.
/// A scene without imagery gets an empty loader (the globe shows its base colour).
Result<std::shared_ptr<globe::TileImageLoader>> openImagery(const std::vector<ImageryLayerDescription>& layers,
                                                           const globe::TileImageLoaderOptions& options);

struct SceneFrameStats {
  GlobeFrameStats globe;
  double cpuMilliseconds = 0.0;  ///< time to issue the frame (without waiting for the GPU)
};

class SceneRendererGL {
 public:
  static Result<std::unique_ptr<SceneRendererGL>> create(std::shared_ptr<globe::TileImageLoader> loader,
                                                         const GlobeRenderOptions& globeOptions = {});
  /// Clears and draws into the bound framebuffer (viewport set by the caller).
  SceneFrameStats renderFrame(const Camera& camera, const std::vector<Marker>& markers);
  /// Renders until the imagery for this view is complete (or `maxPasses` passes), then
  /// reads the image back.
  Result<globe::ImageRGBA8> renderToImage(const Camera& camera, const std::vector<Marker>& markers,
                                          FramebufferGL& target, int maxPasses = 64,
                                          SceneFrameStats* lastStats = nullptr);
  GlobeRendererGL& globe() { return *globe_; }

 private:
  SceneRendererGL() = default;
  std::unique_ptr<GlobeRendererGL> globe_;
  std::unique_ptr<MarkerRendererGL> markers_;
};

}  // namespace atmoglobe::engine
