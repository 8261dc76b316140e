// atmoglobe view: the desktop globe viewer (GLFW window).
//   left drag          orbit (move over the ground)
//   wheel              zoom toward the point under the cursor
//   shift + left drag  tilt (up/down) and turn (left/right)
//   P                  save a screenshot (atmoglobe-screenshot-N.png in the working dir)
//   R                  back to the scene's camera;  Esc/Q  quit
//   Right / Left       next / previous time step of the scene's grids (a substep with
//                      --time-substeps: the grids interpolated in time between steps)
//   Space              play / pause the time steps (looping);  Home  the first step
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/CameraController.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/engine/ViewerPanelGL.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Image.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

namespace atmoglobe::tools {

namespace {

struct ViewOptions {
  SceneOptions scene;
  int frames = 0;            ///< >0: quit after this many frames (scripted use, tests)
  std::string screenshot;    ///< with --frames: save the last frame here
  int timeSubsteps = 1;      ///< frames per time step (interpolated between steps)
  double playSeconds = 0.5;  ///< time per frame while playing
  bool play = false;         ///< start playing (with --frames: one frame per time position)
  bool noPanel = false;      ///< no control panel
  bool noPrefetch = false;   ///< time steps read when shown, not ahead on a worker (docs/memory.md)
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
  bool uiDirty = true;             ///< only the panel must be redrawn (over the last picture)
  int timeMove = 0;                ///< time positions to move by (keys), applied by the loop
  bool timeHome = false;
  bool playing = false;
  bool readoutWanted = false;  ///< the cursor moved: recompute the value under it
  double cursorX = 0, cursorY = 0;
};

/// Where the viewer is on the scene's time axis: position = step * substeps + substep.
struct TimeCursor {
  std::optional<engine::SceneTimeAxis> axis;
  int substeps = 1;
  long position = 0;
  std::string label;  ///< valid time shown
  double lastAdvanceSeconds = 0.0;
  long count() const { return axis ? static_cast<long>(axis->times.size() - 1) * substeps + 1 : 1; }
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
    s.uiDirty = true;
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    if (action == GLFW_PRESS && engine::ViewerPanelGL::capturesMouse()) return;  // a click on the panel
    s.dragging = action == GLFW_PRESS;
    s.tilting = s.dragging && (mods & GLFW_MOD_SHIFT);
    glfwGetCursorPos(win, &s.lastX, &s.lastY);
  });
  glfwSetCursorPosCallback(w, [](GLFWwindow* win, double x, double y) {
    auto& s = *static_cast<Interaction*>(glfwGetWindowUserPointer(win));
    s.uiDirty = true;  // hover highlights in the panel
    if (!s.dragging) {
      s.readoutWanted = true;
      s.cursorX = x;
      s.cursorY = y;
      return;
    }
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
    if (engine::ViewerPanelGL::capturesMouse()) return;
    int width = 0, height = 0;
    glfwGetWindowSize(win, &width, &height);
    double x = 0, y = 0;
    glfwGetCursorPos(win, &x, &y);
    touched(s);
    engine::zoomTowardPixel(s.pose, s.fovYDeg, std::max(width, 1), std::max(height, 1), x, y, std::pow(0.8, yoff));
  });
  glfwSetKeyCallback(w, [](GLFWwindow* win, int key, int, int action, int) {
    auto& s = *static_cast<Interaction*>(glfwGetWindowUserPointer(win));
    if (action != GLFW_PRESS || engine::ViewerPanelGL::capturesKeyboard()) return;
    if (key == GLFW_KEY_ESCAPE || key == GLFW_KEY_Q) glfwSetWindowShouldClose(win, GLFW_TRUE);
    if (key == GLFW_KEY_R) {
      s.pose = s.initial;
      touched(s);
    }
    if (key == GLFW_KEY_P) {
      s.screenshotRequested = true;
      s.dirty = true;
    }
    if (key == GLFW_KEY_RIGHT || key == GLFW_KEY_PERIOD) s.timeMove += 1;
    if (key == GLFW_KEY_LEFT || key == GLFW_KEY_COMMA) s.timeMove -= 1;
    if (key == GLFW_KEY_HOME) s.timeHome = true;
    if (key == GLFW_KEY_SPACE) s.playing = !s.playing;
    s.dirty = true;
  });

  // The scene's time axis, when a grid has several steps or a radar is a loop (time keys and playing).
  TimeCursor time;
  time.substeps = std::clamp(o.timeSubsteps, 1, 100);
  if (!scene->grids.empty() || !scene->radars.empty()) {
    auto axis = engine::sceneTimeAxis(*scene, **renderer);
    if (axis) {
      for (const std::string& note : axis->notes) std::cerr << "atmoglobe view: " << note << "\n";
      const std::size_t first = axis->leadIsRadar ? (*renderer)->radars()[axis->leadGrid].step
                                                  : (*renderer)->grids()[axis->leadGrid].step;
      time.position = static_cast<long>(first) * time.substeps;
      time.label = axis->times[first];
      time.axis = std::move(*axis);
      std::cout << "time: " << time.axis->times[first] << " (step " << first + 1 << " of " << time.axis->times.size()
                << "; Right/Left step, Space plays)" << std::endl;
    }
  }
  state.playing = o.play && time.axis;
  // Background loading (docs/memory.md): the steps after the one shown are read on a worker.
  std::unique_ptr<engine::ScenePrefetcher> prefetch;
  if (time.axis && !o.noPrefetch) prefetch = std::make_unique<engine::ScenePrefetcher>(**renderer, *time.axis);
  if (prefetch) prefetch->request(static_cast<std::size_t>(time.position / time.substeps));
  std::vector<double> stallMs;  // time each step change held the frame loop
  auto showTime = [&](long position) -> Status {
    const long n = time.count();
    position = ((position % n) + n) % n;  // loops at both ends
    if (position == time.position) return Ok{};
    time.position = position;
    const auto step = static_cast<std::size_t>(position / time.substeps);
    const double fraction = static_cast<double>(position % time.substeps) / time.substeps;
    const double stallStart = glfwGetTime();
    auto when = engine::showSceneTime(**renderer, *time.axis, step, fraction);
    if (!when) return when.forwardError();
    stallMs.push_back(1000.0 * (glfwGetTime() - stallStart));
    if (prefetch) prefetch->request(step);
    glfwSetWindowTitle(w, ("atmoglobe  " + *when).c_str());
    time.label = *when;
    std::cout << "time: " << *when << std::endl;
    return Ok{};
  };

  // The control panel, after the window's own callbacks (its backend chains to them).
  std::unique_ptr<engine::ViewerPanelGL> panel;
  if (!o.noPanel) {
    auto p = engine::ViewerPanelGL::create(w);
    if (!p) return fail("view", p.error());
    panel = std::move(*p);
  }
  engine::ViewerPanelState panelState;
  for (const auto& r : (*renderer)->radars())
    panelState.layers.push_back("radar " + r.siteMarker.label + ": " + r.volume->polar().fieldName);
  for (const auto& g : (*renderer)->grids())
    panelState.layers.push_back("grid " + g.volume->grid().variable + " (" + g.description.path + ")");
  double frameMs = 0.0;

  std::vector<double> fullImageScale;
  for (const auto& radar : (*renderer)->radars()) fullImageScale.push_back(radar.options.imageScale);
  std::unique_ptr<engine::FramebufferGL> target;
  int frame = 0;
  bool wasMoving = false;
  while (!glfwWindowShouldClose(w)) {
    const bool moving = glfwGetTime() - state.lastInputSeconds < kSettleSeconds;
    if (!state.dirty && !moving && !wasMoving && !state.playing && (*renderer)->globe().lastFrameComplete() &&
        o.frames == 0) {
      if (state.readoutWanted && panel && target && !engine::ViewerPanelGL::capturesMouse()) {
        state.readoutWanted = false;
        int ww = 0, wh = 0;
        glfwGetWindowSize(w, &ww, &wh);
        // Window coordinates to framebuffer pixels (they differ on high-DPI screens).
        const double sx = ww > 0 ? static_cast<double>(target->widthPx()) / ww : 1.0;
        const double sy = wh > 0 ? static_cast<double>(target->heightPx()) / wh : 1.0;
        const engine::Camera camera(state.pose, state.fovYDeg, target->widthPx(), target->heightPx());
        panelState.readout = engine::readoutAt(**renderer, camera, state.cursorX * sx, state.cursorY * sy).lines;
      }
      if (state.uiDirty && panel && target) {
        // Only the panel changed: the last picture again with the panel over it.
        state.uiDirty = false;
        glBlitNamedFramebuffer(target->id(), 0, 0, 0, target->widthPx(), target->heightPx(), 0, 0, target->widthPx(),
                               target->heightPx(), GL_COLOR_BUFFER_BIT, GL_NEAREST);
        const int before = panelState.timePosition;
        panelState.timePosition = static_cast<int>(time.position);
        panelState.playing = state.playing;
        if (panel->draw(panelState)) {
          state.timeMove += panelState.timePosition - before;
          state.playing = panelState.playing;
          state.dirty = true;
        }
        if (panelState.screenshotRequested) {
          panelState.screenshotRequested = false;
          state.screenshotRequested = true;
          state.dirty = true;
        }
        glfwSwapBuffers(w);
      }
      glfwWaitEventsTimeout(0.1);  // nothing to redraw: sleep until input
      continue;
    }
    glfwPollEvents();
    if (time.axis) {
      long wanted = time.position + state.timeMove;
      if (state.timeHome) wanted = 0;
      const double now = glfwGetTime();
      if (state.playing && (o.frames > 0 || now - time.lastAdvanceSeconds >= o.playSeconds)) {
        wanted += 1;
        time.lastAdvanceSeconds = now;
      }
      state.timeMove = 0;
      state.timeHome = false;
      if (auto st = showTime(wanted); !st) return fail("view", st.error());
    }
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
    const double t0 = glfwGetTime();
    (*renderer)->renderFrame(camera, markers, *target);
    glBlitNamedFramebuffer(target->id(), 0, 0, 0, fbw, fbh, 0, 0, fbw, fbh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glFinish();
    frameMs = 1000.0 * (glfwGetTime() - t0);
    if (panel) {
      state.uiDirty = false;
      panelState.timePositions = time.axis ? static_cast<int>(time.count()) : 0;
      panelState.timePosition = static_cast<int>(time.position);
      panelState.timeLabel = time.label;
      panelState.playing = state.playing;
      panelState.frameMilliseconds = frameMs;
      panelState.legend = (*renderer)->legendFor(camera);
      const int before = panelState.timePosition;
      if (panel->draw(panelState)) {
        state.timeMove += panelState.timePosition - before;
        state.playing = panelState.playing;
        state.dirty = true;
      }
      if (panelState.screenshotRequested) {
        panelState.screenshotRequested = false;
        state.screenshotRequested = true;
        state.dirty = true;
      }
    }
    ++frame;
    const bool last = o.frames > 0 && frame >= o.frames;
    if (state.screenshotRequested || (last && !o.screenshot.empty())) {
      const std::string path = (last && !o.screenshot.empty())
                                   ? o.screenshot
                                   : "atmoglobe-screenshot-" + std::to_string(++state.screenshotCount) + ".png";
      // What the user sees: the scene with the panel over it.
      const globe::ImageRGBA8 shot = panel ? engine::readWindowColorGL(fbw, fbh) : target->readColor();
      if (auto s = globe::writePng(path, shot); !s) return fail("view", s.error());
      std::cout << "screenshot: " << path << std::endl;
      state.screenshotRequested = false;
    }
    glfwSwapBuffers(w);
    if (last) break;
    if (o.frames > 0) (*loader)->waitIdle();  // scripted runs: let imagery arrive between frames
  }
  if (!stallMs.empty()) std::cerr << engine::stallSummary(stallMs, prefetch != nullptr) << "\n";
  return 0;
}
}  // namespace

Command addViewCommand(CLI::App& root) {
  auto options = std::make_shared<ViewOptions>();
  CLI::App* c = root.add_subcommand("view", "Open the desktop globe viewer (needs a display; e.g. xvfb-run -a)");
  addSceneOptions(*c, options->scene);
  c->add_option("--frames", options->frames, "Quit after this many frames (scripted runs)");
  c->add_option("--screenshot", options->screenshot, "With --frames: save the last frame to this PNG");
  c->add_option("--time-substeps", options->timeSubsteps,
                "Time positions per grid time step: between steps the grids are interpolated linearly in time")
      ->capture_default_str();
  c->add_option("--play-seconds", options->playSeconds, "Seconds per time position while playing")
      ->capture_default_str();
  c->add_flag("--play", options->play, "Start playing the time steps (with --frames: one position per frame)");
  c->add_flag("--no-panel", options->noPanel, "No control panel (time slider, layers, frame time, screenshot)");
  c->add_flag("--no-prefetch", options->noPrefetch,
              "Read each time step when it is shown instead of ahead on a worker thread (for comparison)");
  c->footer(
      "Mouse: drag to orbit, wheel to zoom toward the cursor, shift+drag to tilt/turn.\n"
      "Keys: Right/Left next/previous time step, Space play/pause, Home first step, P screenshot, R reset camera, "
      "Esc/Q quit.");
  return {c, [options] { return runView(*options); }};
}

}  // namespace atmoglobe::tools
