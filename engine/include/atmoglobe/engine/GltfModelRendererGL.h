#pragma once
// Draws a georeferenced glTF binary (.glb) the way atmoglobe's cone export writes it: node
// matrices map into the Earth-fixed Y-up frame (X_ecef, Z_ecef, -Y_ecef) of the glTF spec's
// 3D Tiles convention; the model is turned back into ECEF in double and drawn relative to the
// eye. Used to look at an export with the engine itself (render --cones FILE.glb).
// Only what the export uses is supported: triangle primitives with float POSITION and
// TEXCOORD_0, uint32/uint16 indices, a base-colour texture.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/globe/Result.h>

#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::engine {

class GltfModelRendererGL {
 public:
  /// Loads and uploads a .glb; errors name the file and the unsupported or broken part.
  static Result<std::unique_ptr<GltfModelRendererGL>> load(const std::string& path);
  ~GltfModelRendererGL();
  /// Draws into the bound framebuffer with depth test (reverse-Z) and premultiplied blending.
  void draw(const Camera& camera) const;
  std::size_t triangleCount() const;

 private:
  struct PrimitiveGL {
    unsigned int vao = 0, vbo = 0, ibo = 0, texture = 0;
    int indexCount = 0;
    glm::dmat4 modelToEcef{1.0};
    glm::vec4 baseColor{1.0f};
  };
  GltfModelRendererGL() = default;
  ShaderProgramGL program_;
  std::vector<PrimitiveGL> primitives_;
};

}  // namespace atmoglobe::engine
