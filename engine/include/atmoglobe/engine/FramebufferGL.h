#pragma once
// An offscreen render target: colour (RGBA8 by default) + 32-bit float depth (for reverse-Z),
// both textures so later passes can sample them.
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/globe/Result.h>

#include <epoxy/gl.h>

#include <memory>

namespace atmoglobe::engine {

class FramebufferGL {
 public:
  static Result<std::unique_ptr<FramebufferGL>> create(int widthPx, int heightPx, GLenum colorFormat = GL_RGBA8);
  ~FramebufferGL();
  FramebufferGL(const FramebufferGL&) = delete;
  FramebufferGL& operator=(const FramebufferGL&) = delete;

  void bind() const;
  int widthPx() const { return width_; }
  int heightPx() const { return height_; }
  GLuint id() const { return fbo_; }
  GLuint colorTexture() const { return color_; }
  GLuint depthTexture() const { return depth_; }
  /// Reads the colour buffer back; row 0 of the image is the TOP of the picture.
  globe::ImageRGBA8 readColor() const;

 private:
  FramebufferGL() = default;
  int width_ = 0, height_ = 0;
  GLuint fbo_ = 0, color_ = 0, depth_ = 0;
};

/// The current window's back buffer (what the next swap shows: the scene and the panel), top
/// row first, opaque.
globe::ImageRGBA8 readWindowColorGL(int widthPx, int heightPx);

}  // namespace atmoglobe::engine
