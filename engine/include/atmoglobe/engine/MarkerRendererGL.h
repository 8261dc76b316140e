#pragma once
// Station markers: round point sprites at geodetic positions, depth-tested against the
// globe (hidden behind the Earth), positioned relative to the eye in double on the CPU, with
// TrueType labels that do not pile up.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/ShaderProgramGL.h>

#include <memory>
#include <string>
#include <unordered_map>
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
  /// each marker's label beside it (no depth test; labels of markers behind the Earth are left
  /// out): DejaVu Sans (TextRaster.h) in white
  /// with a dark halo, placed so that labels never overlap each other or other markers
  /// (LabelPlacement.h: bigger markers, i.e. radar sites, first; labels with no free slot are
  /// left out). Label textures are made once per distinct text and kept.
  /// depthLift > 1 moves each marker's depth toward the eye by that factor (a marker on
  /// the ground then wins against the ground it sits on).
  void draw(const Camera& camera, const std::vector<Marker>& markers, float depthLift = 1.001f);

 private:
  MarkerRendererGL() = default;
  struct LabelTexture {
    unsigned int texture = 0;  ///< RG8: text coverage, halo coverage
    int widthPx = 0, heightPx = 0;
  };
  static constexpr double kLabelPixelHeight = 15.0;  ///< ascent - descent (px)
  static constexpr double kLabelHaloRadiusPx = 2.0;  ///< dark outline around the glyphs
  void drawLabels(const Camera& camera, const std::vector<Marker>& markers, float depthLift);
  const LabelTexture* labelTexture(const std::string& text);
  std::unordered_map<std::string, LabelTexture> labelTextures_;
  bool fontWarned_ = false;
  MarkerStyle style_ = MarkerStyle::Disc;
  ShaderProgramGL program_;
  ShaderProgramGL labelProgram_;
  unsigned int vao_ = 0, vbo_ = 0;
  unsigned int labelVao_ = 0, labelVbo_ = 0;
};

}  // namespace atmoglobe::engine
