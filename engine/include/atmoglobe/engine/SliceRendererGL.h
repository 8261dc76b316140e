#pragma once
// Slices on the globe: a CAPPI as a curved patch at its height, a cross-section as a vertical
// curtain along its geodesic path, each a mesh textured with the slice's raster coloured through
// the same table as the 3-D view (echo pixels opaque times the layer's opacity; no echo and no
// data transparent) with a thin outline showing where the slice is.
//
// Precision as every layer: vertices are float32 offsets from a double-precision origin (the
// slice's centre), the model-view-projection is computed in double relative to it. The mesh
// follows the surface: cells of at most maxSegmentMeters (5 km: the chord of a 5 km arc of the
// Earth sags 0.5 m below it), the curtain bends exactly at the path's points and runs straight
// up the ellipsoid normal (a point's ECEF is linear in its height along the normal).
// Drawn after the globe and models, before the volumes: the slice writes depth, so the marcher
// stops at it (what is behind is hidden, what is in front is composited over it).
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/engine/SliceLayer.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/Slice.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::engine {

/// A slice's surface (GL-free): positions relative to originEcef with texture coordinates
/// (x, y, z, u, v per vertex; u, v = raster pixel coordinates / raster size, v = 0 at the top
/// row), triangles, and the outline as a closed line strip (x, y, z, u, v).
struct SliceMesh {
  glm::dvec3 originEcef{0.0};
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<float> outline;
};
/// `exaggeration`: heights drawn that many times higher (volume/VerticalExaggeration.h).
SliceMesh buildSliceMesh(const volume::SliceGeometry& geometry, double maxSegmentMeters = 5000.0,
                         double exaggeration = 1.0);

/// The raster's texture: echo pixels in the table's RGB with alpha = opacity (values below the
/// table, no echo and no data: transparent). Row 0 = raster row 0.
globe::ImageRGBA8 sliceTexture(const volume::SliceRaster& raster, const volume::ColorTable& colors, double opacity);

class SliceRendererGL {
 public:
  static Result<std::unique_ptr<SliceRendererGL>> create();
  ~SliceRendererGL();
  SliceRendererGL(const SliceRendererGL&) = delete;
  SliceRendererGL& operator=(const SliceRendererGL&) = delete;

  /// Reads the slice's volume (only its field and time step), samples the slice at
  /// resolutionPx along its longer side, uploads it. Returns a line for the user ("KTLX DBZ
  /// CAPPI at 3000 m above sea level: 512 x 480 px, 1234 echo"). Errors: the source's, the
  /// request's (SliceSource.h), the colours'.
  Result<std::string> add(const SliceLayerDescription& description);
  /// Uploads a slice already sampled.
  void add(const volume::SliceGeometry& geometry, const volume::SliceRaster& raster, const volume::ColorTable& colors,
           double opacity);
  /// Draws every slice into the bound framebuffer (reverse-Z depth test and writes, premultiplied
  /// blending).
  void draw(const Camera& camera) const;
  std::size_t size() const { return slices_.size(); }
  /// The scene's vertical exaggeration for slices added from now on (1: none).
  void setVerticalExaggeration(double factor) { exaggeration_ = factor; }

 private:
  struct SliceGL {
    unsigned int vao = 0, vbo = 0, ibo = 0, outlineVao = 0, outlineVbo = 0, texture = 0;
    int indexCount = 0, outlineCount = 0;
    glm::dvec3 originEcef{0.0};
  };
  SliceRendererGL() = default;
  ShaderProgramGL program_;
  std::vector<SliceGL> slices_;
  double exaggeration_ = 1.0;
};

}  // namespace atmoglobe::engine
