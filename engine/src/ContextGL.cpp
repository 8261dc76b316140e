#include <atmoglobe/engine/ContextGL.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <mutex>
#include <sstream>

namespace atmoglobe::engine {

std::string describeCurrentContextGL() {
  std::ostringstream s;
  s << reinterpret_cast<const char*>(glGetString(GL_RENDERER)) << " / OpenGL "
    << reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return s.str();
}

Result<std::unique_ptr<HeadlessContextGL>> HeadlessContextGL::create() {
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!getPlatformDisplay) return makeError("EGL: eglGetPlatformDisplayEXT is not available");
  // Mesa's surfaceless platform (llvmpipe and Mesa GPU drivers); else the first EGL device that
  // initialises (EGL_EXT_platform_device: NVIDIA's driver without a display).
  EGLint major = 0, minor = 0;
  EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display != EGL_NO_DISPLAY && !eglInitialize(display, &major, &minor)) display = EGL_NO_DISPLAY;
  if (display == EGL_NO_DISPLAY) {
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLDeviceEXT devices[8];
    EGLint count = 0;
    if (queryDevices && queryDevices(8, devices, &count)) {
      for (EGLint i = 0; i < count && display == EGL_NO_DISPLAY; ++i) {
        display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (display != EGL_NO_DISPLAY && !eglInitialize(display, &major, &minor)) display = EGL_NO_DISPLAY;
      }
    }
  }
  if (display == EGL_NO_DISPLAY) {
    return makeError(
        "EGL: no display on the Mesa surfaceless platform nor on an EGL device (is libegl-mesa0 installed?)");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    eglTerminate(display);
    return makeError("EGL: desktop OpenGL API not available");
  }
  const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint numConfigs = 0;
  if (!eglChooseConfig(display, configAttribs, &config, 1, &numConfigs) || numConfigs < 1) {
    config = nullptr;  // surfaceless: EGL_KHR_no_config_context lets us go on without one
  }
  const EGLint contextAttribs[] = {
      EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
  if (context == EGL_NO_CONTEXT) {
    eglTerminate(display);
    return makeError("EGL: could not create an OpenGL 4.5 core context");
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    eglTerminate(display);
    return makeError("EGL: eglMakeCurrent without a surface failed");
  }
  std::unique_ptr<HeadlessContextGL> out(new HeadlessContextGL());
  out->display_ = display;
  out->context_ = context;
  return out;
}

HeadlessContextGL::~HeadlessContextGL() {
  if (display_) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_) eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
}

std::string HeadlessContextGL::describe() const { return describeCurrentContextGL(); }

namespace {
std::string g_glfwError;
void onGlfwError(int, const char* message) { g_glfwError = message ? message : "unknown"; }
}  // namespace

Result<std::unique_ptr<WindowGL>> WindowGL::create(int widthPx, int heightPx, const std::string& title) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) return makeError("GLFW: cannot initialise (no display? run under xvfb-run): " + g_glfwError);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* w = glfwCreateWindow(widthPx, heightPx, title.c_str(), nullptr, nullptr);
  if (!w) {
    glfwTerminate();
    return makeError("GLFW: cannot create a window with an OpenGL 4.5 core context: " + g_glfwError);
  }
  glfwMakeContextCurrent(w);
  glfwSwapInterval(1);
  std::unique_ptr<WindowGL> out(new WindowGL());
  out->window_ = w;
  return out;
}

WindowGL::~WindowGL() {
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

}  // namespace atmoglobe::engine
