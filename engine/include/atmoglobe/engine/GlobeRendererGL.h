#pragma once
// Draws the WGS84 globe: selects tiles for the camera (globe::selectTiles), builds their
// meshes (float32 relative to each tile's double centre), uploads imagery decoded off the
// render thread (globe::TileImageLoader) and draws each tile with a model-view-projection
// computed in double relative to the eye. GPU meshes and textures live in byte-budgeted
// LRU caches.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/globe/LruCache.h>
#include <atmoglobe/globe/TileId.h>
#include <atmoglobe/globe/TileImageLoader.h>
#include <atmoglobe/globe/TileSelection.h>

#include <memory>

namespace atmoglobe::engine {

struct GlobeRenderOptions {
  double maxScreenSpaceErrorPx = 2.0;        ///< refine tiles until their error is below this
  int meshSegments = 16;                     ///< quads per tile edge
  std::size_t gpuBudgetBytes = 256u << 20;   ///< meshes + textures kept on the GPU
  glm::vec3 baseColor{0.05f, 0.09f, 0.18f};  ///< where no imagery is resident yet
};

struct GlobeFrameStats {
  globe::SelectionStats selection;
  int tilesDrawn = 0;
  int tilesWithFallbackImagery = 0;  ///< drawn with an ancestor's (coarser) imagery or the base colour
  int meshesBuilt = 0;
  int texturesUploaded = 0;
  std::size_t gpuBytes = 0;
};

class GlobeRendererGL {
 public:
  static Result<std::unique_ptr<GlobeRendererGL>> create(std::shared_ptr<globe::TileImageLoader> loader,
                                                         const GlobeRenderOptions& options);
  ~GlobeRendererGL();

  /// Draws into the bound framebuffer (depth state set by the caller: reverse-Z).
  GlobeFrameStats draw(const Camera& camera);
  /// True if the last draw used, for every tile, the imagery it wanted (nothing pending).
  bool lastFrameComplete() const { return lastFrameComplete_; }
  globe::TileImageLoader& loader() { return *loader_; }

  struct MeshGL;     ///< GPU mesh of one tile (private to the .cpp)
  struct TextureGL;  ///< GPU imagery of one tile (private to the .cpp)

 private:
  GlobeRendererGL() = default;
  const TextureGL* findTexture(const globe::TileId& imageryTile, double priority, GlobeFrameStats& stats,
                               bool* pending);

  std::shared_ptr<globe::TileImageLoader> loader_;
  GlobeRenderOptions options_;
  ShaderProgramGL program_;
  int uMvp_ = -1, uUvTransform_ = -1, uHasImagery_ = -1, uBaseColor_ = -1, uImagery_ = -1;
  std::unique_ptr<globe::LruCache<globe::TileId, std::shared_ptr<MeshGL>, globe::TileIdHash>> meshes_;
  std::unique_ptr<globe::LruCache<globe::TileId, std::shared_ptr<TextureGL>, globe::TileIdHash>> textures_;
  bool lastFrameComplete_ = false;
};

}  // namespace atmoglobe::engine
