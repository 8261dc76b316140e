#pragma once
// An offscreen render target: colour (RGBA8 by default) + 32-bit float depth (for reverse-Z),
// both textures so later passes can sample them. GL names and enums are plain `unsigned int`
// here (GLuint, GLenum), so that including this header needs no GL loader.
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/Result.h>

#include <memory>

namespace atmoglobe::engine {

class FramebufferGL {
 public:
  /// RGBA8 colour.
  static Result<std::unique_ptr<FramebufferGL>> create(int widthPx, int heightPx);
  /// `colorFormat`: a GL sized internal format (GL_RGBA16F, GL_RGBA32F, ...).
  static Result<std::unique_ptr<FramebufferGL>> create(int widthPx, int heightPx, unsigned int colorFormat);
  ~FramebufferGL();
  FramebufferGL(const FramebufferGL&) = delete;
  FramebufferGL& operator=(const FramebufferGL&) = delete;

  void bind() const;
  int widthPx() const { return width_; }
  int heightPx() const { return height_; }
  unsigned int id() const { return fbo_; }
  unsigned int colorTexture() const { return color_; }
  unsigned int depthTexture() const { return depth_; }
  /// Reads the colour buffer back; row 0 of the image is the TOP of the picture.
  globe::ImageRGBA8 readColor() const;

 private:
  FramebufferGL() = default;
  int width_ = 0, height_ = 0;
  unsigned int fbo_ = 0, color_ = 0, depth_ = 0;
};

/// The current window's back buffer (what the next swap shows: the scene and the panel), top
/// row first, opaque.
globe::ImageRGBA8 readWindowColorGL(int widthPx, int heightPx);

}  // namespace atmoglobe::engine
