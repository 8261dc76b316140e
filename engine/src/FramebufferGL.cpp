#include <atmoglobe/engine/FramebufferGL.h>

#include "LoaderGL.h"

#include <cstring>
#include <string>

namespace atmoglobe::engine {

Result<std::unique_ptr<FramebufferGL>> FramebufferGL::create(int widthPx, int heightPx) {
  return create(widthPx, heightPx, GL_RGBA8);
}

Result<std::unique_ptr<FramebufferGL>> FramebufferGL::create(int widthPx, int heightPx, GLenum colorFormat) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
  if (widthPx < 1 || heightPx < 1 || widthPx > maxSize || heightPx > maxSize) {
    return makeError("image size " + std::to_string(widthPx) + "x" + std::to_string(heightPx) + " is outside 1.." +
                     std::to_string(maxSize));
  }
  std::unique_ptr<FramebufferGL> fb(new FramebufferGL());
  fb->width_ = widthPx;
  fb->height_ = heightPx;
  glCreateFramebuffers(1, &fb->fbo_);
  // Textures (not renderbuffers) so later passes can sample the globe's colour and depth.
  glCreateTextures(GL_TEXTURE_2D, 1, &fb->color_);
  glTextureStorage2D(fb->color_, 1, colorFormat, widthPx, heightPx);
  glCreateTextures(GL_TEXTURE_2D, 1, &fb->depth_);
  glTextureStorage2D(fb->depth_, 1, GL_DEPTH_COMPONENT32F, widthPx, heightPx);
  for (GLuint t : {fb->color_, fb->depth_}) {
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  glTextureParameteri(fb->depth_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(fb->depth_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glNamedFramebufferTexture(fb->fbo_, GL_COLOR_ATTACHMENT0, fb->color_, 0);
  glNamedFramebufferTexture(fb->fbo_, GL_DEPTH_ATTACHMENT, fb->depth_, 0);
  if (glCheckNamedFramebufferStatus(fb->fbo_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    return makeError("framebuffer " + std::to_string(widthPx) + "x" + std::to_string(heightPx) + " is incomplete");
  }
  return fb;
}

FramebufferGL::~FramebufferGL() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (color_) glDeleteTextures(1, &color_);
  if (depth_) glDeleteTextures(1, &depth_);
}

void FramebufferGL::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width_, height_);
}

namespace {
// RGBA8 of a framebuffer's colour (top row first).
globe::ImageRGBA8 readColorOf(GLuint fbo, GLenum buffer, int width, int height) {
  globe::ImageRGBA8 image;
  image.width = width;
  image.height = height;
  const std::size_t rowBytes = static_cast<std::size_t>(width) * 4;
  std::vector<std::uint8_t> raw(rowBytes * static_cast<std::size_t>(height));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glReadBuffer(buffer);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
  image.pixels.resize(raw.size());
  for (int y = 0; y < height; ++y) {  // GL rows start at the bottom
    std::memcpy(image.pixels.data() + static_cast<std::size_t>(y) * rowBytes,
                raw.data() + static_cast<std::size_t>(height - 1 - y) * rowBytes, rowBytes);
  }
  return image;
}
}  // namespace

globe::ImageRGBA8 FramebufferGL::readColor() const { return readColorOf(fbo_, GL_COLOR_ATTACHMENT0, width_, height_); }

globe::ImageRGBA8 readWindowColorGL(int widthPx, int heightPx) {
  globe::ImageRGBA8 image = readColorOf(0, GL_BACK, widthPx, heightPx);
  for (std::size_t n = 3; n < image.pixels.size(); n += 4) image.pixels[n] = 255;  // the window is opaque
  return image;
}

}  // namespace atmoglobe::engine
