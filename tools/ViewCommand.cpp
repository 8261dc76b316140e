// atmoglobe view: the desktop globe viewer (GLFW window).
//   left drag          orbit (move over the ground)
//   wheel              zoom toward the point under the cursor
//   shift + left drag  tilt (up/down) and turn (left/right)
//   P                  save a screenshot (atmoglobe-screenshot-N.png in the working dir)
//   R                  back to the scene's camera;  Esc/Q  quit
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/CameraController.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Image.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

namespace atmoglobe::tools {

namespace {

struct ViewOptions {
  SceneOptions scene;
  int frames = 0;          ///< >0: quit after this many frames (scripted use, tests)
  std::string screenshot;  ///< with --frames: save the last frame here
};

struct Interaction {
  engine::CameraPose pose;
  engine::CameraPose initial;
  bool dragging = false;
  bool tilting = false;
  double lastX = 0, lastY = 0;
  double fovYDeg = 60;
  int screenshotCount = 0;
  bool screenshotRequested = false;
  double lastInputSeconds = -1e9;  ///< glfwGetTime() of the last camera change
  bool dirty = true;               ///< the picture must be redrawn
};

/// While the camera moves (input in the last kSettleSeconds) volumes are marched at
/// kMovingImageScale of their resolution; once it rests, one full-quality frame is drawn
/// and nothing more until something changes.
constexpr double kSettleSeconds = 0.3;
constexpr double kMovingImageScale = 0.25;

void touched(Interaction& s) {
  s.lastInputSeconds = glfwGetTime();
  s.dirty = true;
}

int runView(const ViewOptions& o) {
  auto scene = resolveScene(o.scene);
  if (!scene) return fail("view", scene.error());
  auto window = engine::WindowGL::create(scene->widthPx, scene->heightPx, "atmoglobe");
  if (!window) return fail("view", window.error());
  auto loader = engine::openImagery(scene->imagery, {});
  if (!loader) return fail("view", loader.error());
  auto renderer = engine::SceneRendererGL::create(*loader);
  if (!renderer) return fail("view", renderer.error());
  std::vector<engine::Marker> markers = scene->markers;
  if (auto s = populateScene(**renderer, *scene, &markers); !s) return fail("view", s.error());

  Interaction state;
  state.pose = state.initial = scene->camera;
  state.fovYDeg = scene->fovYDeg;
  GLFWwindow* w = (*window)->handle();
  glfwSetWindowUserPointer(w, &state);
  glfwSetMouseButtonCallback(w, [](GLFWwindow* win, int button, int action, int mods) {
    auto& s = *static_cast<Interaction*>(glfwGetWindowUserPointer(win));
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    s.dragging = action == GLFW_PRESS;
    s.tilting = s.dragging && (mods & GLFW_MOD_SHIFT);
    glfwGetCursorPos(win, &s.lastX, &s.lastY);
  });
  glfwSetCursorPosCallback(w, [](GLFWwindow* win, double x, double y) {
    auto& s = *static_cast<Interaction*>(glfwGetWindowUserPointer(win));
    if (!s.dragging) return;
    int width = 0, height = 0;
    glfwGetWindowSize(win, &width, &height);
    const double dx = x - s.lastX, dy = y - s.lastY;
    s.lastX = x;
    s.lastY = y;
    touched(s);
    if (s.tilting) {
      engine::tiltByPixels(s.pose, dx, dy);
    } else {
      engine::orbitByPixels(s.pose, s.fovYDeg, std::max(height, 1), dx, dy);
    }
  });
  glfwSetScrollCallback(w, [](GLFWwindow* win, double, double yoff) {
    auto& s = *static_cast<Interaction*>(glfwGetWindowUserPointer(win));
    int width = 0, height = 0;
    glfwGetWindowSize(win, &width, &height);
    double x = 0, y = 0;
    glfwGetCursorPos(win, &x, &y);
    touched(s);
    engine::zoomTowardPixel(s.pose, s.fovYDeg, std::max(width, 1), std::max(height, 1), x, y, std::pow(0.8, yoff));
  });
  glfwSetKeyCallback(w, [](GLFWwindow* win, int key, int, int action, int) {
    auto& s = *static_cast<Interaction*>(glfwGetWindowUserPointer(win));
    if (action != GLFW_PRESS) return;
    if (key == GLFW_KEY_ESCAPE || key == GLFW_KEY_Q) glfwSetWindowShouldClose(win, GLFW_TRUE);
    if (key == GLFW_KEY_R) {
      s.pose = s.initial;
      touched(s);
    }
    if (key == GLFW_KEY_P) {
      s.screenshotRequested = true;
      s.dirty = true;
    }
  });

  std::vector<double> fullImageScale;
  for (const auto& radar : (*renderer)->radars()) fullImageScale.push_back(radar.options.imageScale);
  std::unique_ptr<engine::FramebufferGL> target;
  int frame = 0;
  bool wasMoving = false;
  while (!glfwWindowShouldClose(w)) {
    const bool moving = glfwGetTime() - state.lastInputSeconds < kSettleSeconds;
    if (!state.dirty && !moving && !wasMoving && (*renderer)->globe().lastFrameComplete() && o.frames == 0) {
      glfwWaitEventsTimeout(0.1);  // nothing to redraw: sleep until input
      continue;
    }
    glfwPollEvents();
    auto& radars = (*renderer)->radars();
    for (std::size_t i = 0; i < radars.size(); ++i) {
      radars[i].options.imageScale = moving ? std::min(fullImageScale[i], kMovingImageScale) : fullImageScale[i];
    }
    wasMoving = moving;
    state.dirty = false;
    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(w, &fbw, &fbh);
    if (fbw < 1 || fbh < 1) continue;
    if (!target || target->widthPx() != fbw || target->heightPx() != fbh) {
      auto t = engine::FramebufferGL::create(fbw, fbh);
      if (!t) return fail("view", t.error());
      target = std::move(*t);
    }
    const engine::Camera camera(state.pose, state.fovYDeg, fbw, fbh);
    // Our own target has a float depth buffer (reverse-Z); the window's may not.
    (*renderer)->renderFrame(camera, markers, *target);
    glBlitNamedFramebuffer(target->id(), 0, 0, 0, fbw, fbh, 0, 0, fbw, fbh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    ++frame;
    const bool last = o.frames > 0 && frame >= o.frames;
    if (state.screenshotRequested || (last && !o.screenshot.empty())) {
      const std::string path = (last && !o.screenshot.empty())
                                   ? o.screenshot
                                   : "atmoglobe-screenshot-" + std::to_string(++state.screenshotCount) + ".png";
      if (auto s = globe::writePng(path, target->readColor()); !s) return fail("view", s.error());
      std::cout << "screenshot: " << path << std::endl;
      state.screenshotRequested = false;
    }
    glfwSwapBuffers(w);
    if (last) break;
    if (o.frames > 0) (*loader)->waitIdle();  // scripted runs: let imagery arrive between frames
  }
  return 0;
}
}  // namespace

Command addViewCommand(CLI::App& root) {
  auto options = std::make_shared<ViewOptions>();
  CLI::App* c = root.add_subcommand("view", "Open the desktop globe viewer (needs a display; e.g. xvfb-run -a)");
  addSceneOptions(*c, options->scene);
  c->add_option("--frames", options->frames, "Quit after this many frames (scripted runs)");
  c->add_option("--screenshot", options->screenshot, "With --frames: save the last frame to this PNG");
  c->footer(
      "Mouse: drag to orbit, wheel to zoom toward the cursor, shift+drag to tilt/turn.\n"
      "Keys: P screenshot, R reset camera, Esc/Q quit.");
  return {c, [options] { return runView(*options); }};
}

}  // namespace atmoglobe::tools
