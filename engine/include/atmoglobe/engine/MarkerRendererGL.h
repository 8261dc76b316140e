#pragma once
// Station markers: round point sprites at geodetic positions, depth-tested against the
// globe (hidden behind the Earth), positioned relative to the eye in double on the CPU.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/ShaderProgramGL.h>

#include <epoxy/gl.h>

#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::engine {

enum class MarkerStyle {
  Disc,      ///< solid disc with a dark rim (what users see)
  Gaussian,  ///< premultiplied Gaussian blob around the exact centre (precision tests)
};

class MarkerRendererGL {
 public:
  static Result<std::unique_ptr<MarkerRendererGL>> create(MarkerStyle style);
  ~MarkerRendererGL();
  /// Draws into the bound framebuffer, depth-tested against what is already there, with
  /// each marker's label (stb_easy_font, 2x scale) beside it at the marker's depth.
  /// depthLift > 1 moves each marker's depth toward the eye by that factor (a marker on
  /// the ground then wins against the ground it sits on).
  void draw(const Camera& camera, const std::vector<Marker>& markers, float depthLift = 1.001f);

 private:
  MarkerRendererGL() = default;
  void drawLabels(const Camera& camera, const std::vector<Marker>& markers, float depthLift);
  MarkerStyle style_ = MarkerStyle::Disc;
  ShaderProgramGL program_;
  ShaderProgramGL labelProgram_;
  GLuint vao_ = 0, vbo_ = 0;
  GLuint labelVao_ = 0, labelVbo_ = 0;
};

}  // namespace atmoglobe::engine
