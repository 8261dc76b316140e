#pragma once
// OpenGL 4.5 core contexts: headless (EGL, Mesa surfaceless platform: no X server, no
// GPU needed) and windowed (GLFW). Functions are loaded through libepoxy.
#include <atmoglobe/globe/Result.h>

#include <memory>
#include <string>

struct GLFWwindow;

namespace atmoglobe::engine {

/// A current GL 4.5 core context with no default framebuffer (render into an FBO).
class HeadlessContextGL {
 public:
  /// Creates the context and makes it current on this thread. Error when EGL, the
  /// surfaceless platform or a 4.5 core context is unavailable (message says which).
  static Result<std::unique_ptr<HeadlessContextGL>> create();
  ~HeadlessContextGL();
  HeadlessContextGL(const HeadlessContextGL&) = delete;
  HeadlessContextGL& operator=(const HeadlessContextGL&) = delete;

  /// GL_RENDERER / GL_VERSION strings, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string describe() const;

 private:
  HeadlessContextGL() = default;
  void* display_ = nullptr;
  void* context_ = nullptr;
};

/// A GLFW window with a current GL 4.5 core context.
class WindowGL {
 public:
  static Result<std::unique_ptr<WindowGL>> create(int widthPx, int heightPx, const std::string& title);
  ~WindowGL();
  WindowGL(const WindowGL&) = delete;
  WindowGL& operator=(const WindowGL&) = delete;
  GLFWwindow* handle() const { return window_; }

 private:
  WindowGL() = default;
  GLFWwindow* window_ = nullptr;
};

/// GL_RENDERER and GL_VERSION of the current context.
std::string describeCurrentContextGL();

}  // namespace atmoglobe::engine
