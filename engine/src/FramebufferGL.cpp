#include <atmoglobe/engine/FramebufferGL.h>

#include <cstring>
#include <string>

namespace atmoglobe::engine {

Result<std::unique_ptr<FramebufferGL>> FramebufferGL::create(int widthPx, int heightPx) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
  if (widthPx < 1 || heightPx < 1 || widthPx > maxSize || heightPx > maxSize) {
    return makeError("image size " + std::to_string(widthPx) + "x" + std::to_string(heightPx) +
                     " is outside 1.." + std::to_string(maxSize));
  }
  std::unique_ptr<FramebufferGL> fb(new FramebufferGL());
  fb->width_ = widthPx;
  fb->height_ = heightPx;
  glCreateFramebuffers(1, &fb->fbo_);
  glCreateRenderbuffers(1, &fb->color_);
  glNamedRenderbufferStorage(fb->color_, GL_RGBA8, widthPx, heightPx);
  glCreateRenderbuffers(1, &fb->depth_);
  glNamedRenderbufferStorage(fb->depth_, GL_DEPTH_COMPONENT32F, widthPx, heightPx);
  glNamedFramebufferRenderbuffer(fb->fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, fb->color_);
  glNamedFramebufferRenderbuffer(fb->fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, fb->depth_);
  if (glCheckNamedFramebufferStatus(fb->fbo_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    return makeError("framebuffer " + std::to_string(widthPx) + "x" + std::to_string(heightPx) + " is incomplete");
  }
  return fb;
}

FramebufferGL::~FramebufferGL() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (color_) glDeleteRenderbuffers(1, &color_);
  if (depth_) glDeleteRenderbuffers(1, &depth_);
}

void FramebufferGL::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width_, height_);
}

globe::ImageRGBA8 FramebufferGL::readColor() const {
  globe::ImageRGBA8 image;
  image.width = width_;
  image.height = height_;
  const std::size_t rowBytes = static_cast<std::size_t>(width_) * 4;
  std::vector<std::uint8_t> raw(rowBytes * static_cast<std::size_t>(height_));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
  image.pixels.resize(raw.size());
  for (int y = 0; y < height_; ++y) {  // GL rows start at the bottom
    std::memcpy(image.pixels.data() + static_cast<std::size_t>(y) * rowBytes,
                raw.data() + static_cast<std::size_t>(height_ - 1 - y) * rowBytes, rowBytes);
  }
  return image;
}

}  // namespace atmoglobe::engine
