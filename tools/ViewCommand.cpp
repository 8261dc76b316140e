// atmoglobe view: the desktop globe viewer (GLFW window). Navigation (engine/CameraController.h):
//   left drag             grab the globe: the ground point under the pointer stays under it
//                         (the globe turns about its centre; at any tilt)
//   wheel                 zoom toward the point under the cursor (exact at any tilt)
//   shift + left drag,    tilt (up/down) and turn (left/right) about the ground point at the
//   right drag            view centre
//   arrows, W A S D       move (the ground at the centre slides by a tenth of the view)
//   shift + Left/Right    turn about the view centre
//   + / -                 zoom in / out at the view centre
//   PageUp / PageDown     tilt toward the horizon / back toward straight down
//   H or R                fly home (the scene's camera)
//   Fly-to box (panel)    fly to a radar, station, place or LAT,LON; also --fly-to NAME
// Time (scene grids and radar loops):
//   . / ,                 next / previous time step (a substep with --time-substeps)
//   Space                 play / pause (looping);  Home  the first step
// Other: P  screenshot (atmoglobe-screenshot-N.png in the working directory);  Ctrl+S  save the
// scene shown (--save-scene, default atmoglobe-scene.json);  Esc/Q  quit.
// (Right/Left used to step time; arrows now move the camera, as in globe viewers, and time
// keeps the , . keys it already had.)
//
// --script FILE (engine/ViewerScript.h) replays mouse, wheel, key and text input through the very
// callbacks GLFW calls (the ones installed on the window, so the panel's ImGui backend sees them
// too), one step per frame, plus camera jumps, waits, flights and screenshots; the value under
// the pointer is printed as `readout: ...` lines. Then --frames more frames (default 1) are drawn
// and --screenshot saved.
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/CameraController.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FlyToWindowGL.h>
#include <atmoglobe/engine/FramePacing.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/Gazetteer.h>
#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/SceneTime.h>
#include <atmoglobe/engine/ViewCulling.h>
#include <atmoglobe/engine/ViewerPanelGL.h>
#include <atmoglobe/engine/ViewerScript.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/AtomicFile.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/StationList.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
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
  std::string script;        ///< --script FILE
  std::string flyTo;         ///< --fly-to NAME: start above it
  bool noPrefetch = false;   ///< time steps read when shown, not ahead on a worker (docs/memory.md)
  std::string saveScene = "atmoglobe-scene.json";  ///< where Ctrl+S / "Save scene" writes
  std::string frameLog;                            ///< --frame-log FILE: a CSV line per scene drawn
  double refineMs = -1.0;    ///< --refine-ms: at-rest marching per frame; < 0: kRefineBudgetMs, whole frames in scripts
  double movingScale = 0.0;  ///< --moving-scale: volumes' image scale while moving; 0: paced (engine/FramePacing.h)
  bool loadAll = false;  ///< --load-all: radars outside the first view loaded at start, not when they come into view
};

struct Flight {
  engine::CameraPose from, to;
  double startSeconds = 0.0;
  double seconds = 1.0;
};

struct Interaction {
  engine::CameraPose pose;
  engine::CameraPose initial;
  bool dragging = false;
  bool tilting = false;
  std::optional<glm::dvec3> grabbed;  ///< the ground point held by a drag (none: pressed on the sky)
  double lastX = 0, lastY = 0;
  double fovYDeg = 60;
  int screenshotCount = 0;
  bool screenshotRequested = false;
  std::string screenshotPath;       ///< a script's screenshot file
  bool saveSceneRequested = false;  ///< Ctrl+S or the panel's "Save scene"
  double lastInputSeconds = -1e9;   ///< glfwGetTime() of the last camera change
  bool dirty = true;                ///< the picture must be redrawn
  bool uiDirty = true;              ///< only the panel must be redrawn (over the last picture)
  int timeMove = 0;                 ///< time positions to move by (keys), applied by the loop
  bool timeHome = false;
  bool playing = false;
  bool readoutWanted = false;  ///< the cursor moved: recompute the value under it
  double cursorX = 0, cursorY = 0;
  std::optional<Flight> flight;
  bool flyHome = false;
  bool scripted = false;
  double scriptSeconds = 0.0;  ///< a script's clock: kScriptFrameSeconds per frame
};

/// While the camera moves (input in the last kSettleSeconds) volumes are marched at a reduced
/// image scale that follows the frame times (engine::MovingImageScale: at most a quarter, less
/// where a quarter would take longer than 40 ms a frame); once it rests, the full-quality volumes are refined
/// over frames of at most kRefineBudgetMs of marching, and nothing more is drawn until something
/// changes.
constexpr double kSettleSeconds = 0.3;
/// At rest the full-quality volumes are marched in tiles, at most this long a frame
/// (SceneRendererGL::setProgressiveBudget), input handled between frames; scripts and --frames
/// runs draw each frame whole (deterministic).
constexpr double kRefineBudgetMs = 20.0;
/// Milliseconds a frame may spend reading and building map lines (MapRendererGL::setBuildBudgetMs).
constexpr double kMapBuildBudgetMs = 8.0;
/// Milliseconds a frame may spend making a network's far-field slabs (FarFieldGL.h), the network
/// marched meanwhile: 159 radars' slabs took 20 s at once at 1280x720 on llvmpipe, a stalled
/// viewer (VolumeRendererGL::setFarFieldBuildBudgetMs).
constexpr double kFarFieldBuildBudgetMs = 20.0;
/// A script's clock runs at this many seconds per frame (flights take a fixed number of frames).
constexpr double kScriptFrameSeconds = 0.25;
constexpr double kPanFraction = 0.1;      ///< arrows/WASD: a tenth of the view
constexpr double kKeyZoomFactor = 0.7;    ///< + / -
constexpr double kKeyTiltDeg = 5.0;       ///< PageUp / PageDown
constexpr double kKeyTurnDeg = 10.0;      ///< shift + Left / Right
constexpr double kDegreesPerPixel = 0.2;  ///< tilt/turn drags

/// Where the viewer is on the scene's time axis (position = step * substeps + substep), the
/// background loader of the steps ahead (docs/memory.md), and what stepping cost the frame loop.
struct TimeCursor {
  std::optional<engine::SceneTimeAxis> axis;
  int substeps = 1;
  long position = 0;
  std::string label;  ///< valid time shown
  double lastAdvanceSeconds = 0.0;
  std::unique_ptr<engine::ScenePrefetcher> prefetch;
  std::vector<double> stallMs;  ///< time each step change held the frame loop
  long count() const { return axis ? static_cast<long>(axis->times.size() - 1) * substeps + 1 : 1; }

  /// The scene's axis at the step its lead layer shows (none: no layer has several times; said
  /// on stdout), and the prefetcher when `prefetchAhead`.
  void start(engine::SceneRendererGL& renderer, int substepsPerStep, bool prefetchAhead) {
    substeps = std::clamp(substepsPerStep, 1, 100);
    auto found = engine::sceneTimeAxis(renderer);
    if (!found) return;
    for (const std::string& note : found->notes) std::cerr << "atmoglobe view: " << note << "\n";
    const std::size_t first = renderer.layer(found->leadLayer).step();
    position = static_cast<long>(first) * substeps;
    label = found->times[first];
    axis = std::move(*found);
    std::cout << "time: " << axis->times[first] << " (step " << first + 1 << " of " << axis->times.size()
              << "; . and , step, Space plays)" << std::endl;
    if (prefetchAhead) {
      prefetch = std::make_unique<engine::ScenePrefetcher>(renderer, *axis);
      prefetch->request(first);
    }
  }

  /// Moves to `to` (looping at both ends): the valid time shown when it changed, else nullopt.
  Result<std::optional<std::string>> moveTo(engine::SceneRendererGL& renderer, long to) {
    const long n = count();
    to = ((to % n) + n) % n;
    if (to == position) return std::optional<std::string>();
    position = to;
    const auto step = static_cast<std::size_t>(to / substeps);
    const double fraction = static_cast<double>(to % substeps) / substeps;
    const double stallStart = glfwGetTime();
    auto when = engine::showSceneTime(renderer, *axis, step, fraction);
    if (!when) return when.forwardError();
    stallMs.push_back(1000.0 * (glfwGetTime() - stallStart));
    if (prefetch) prefetch->request(step);
    label = *when;
    return std::optional<std::string>(*when);
  }
};

Interaction& stateOf(GLFWwindow* win) { return *static_cast<Interaction*>(glfwGetWindowUserPointer(win)); }

void windowSize(GLFWwindow* win, int* width, int* height) {
  glfwGetWindowSize(win, width, height);
  *width = std::max(*width, 1);
  *height = std::max(*height, 1);
}

double clockSeconds(const Interaction& s) { return s.scripted ? s.scriptSeconds : glfwGetTime(); }

void touched(Interaction& s) {
  s.lastInputSeconds = glfwGetTime();
  s.dirty = true;
}

/// The user moved the camera: a flight under way stops where it is.
void userMoved(Interaction& s) {
  s.flight.reset();
  touched(s);
}

void startFlight(Interaction& s, const engine::CameraPose& to) {
  s.flight = Flight{s.pose, to, clockSeconds(s), engine::flightSeconds(s.pose, to)};
  touched(s);
}

// The window's input callbacks. A script calls them too (through the callbacks installed on the
// window, which the panel's ImGui backend chains to these).
void onMouseButton(GLFWwindow* win, int button, int action, int mods) {
  auto& s = stateOf(win);
  s.uiDirty = true;
  if (button != GLFW_MOUSE_BUTTON_LEFT && button != GLFW_MOUSE_BUTTON_RIGHT) return;
  if (action != GLFW_PRESS) {
    s.dragging = false;
    s.grabbed.reset();
    s.readoutWanted = true;
    return;
  }
  if (engine::ViewerPanelGL::capturesMouse()) return;  // a click on the panel
  int width = 0, height = 0;
  windowSize(win, &width, &height);
  s.dragging = true;
  s.tilting = button == GLFW_MOUSE_BUTTON_RIGHT || (mods & GLFW_MOD_SHIFT);
  s.lastX = s.cursorX;
  s.lastY = s.cursorY;
  s.grabbed.reset();
  if (!s.tilting) s.grabbed = engine::groundUnderPixel(s.pose, s.fovYDeg, width, height, s.cursorX, s.cursorY);
  s.flight.reset();
}

void onCursorPos(GLFWwindow* win, double x, double y) {
  auto& s = stateOf(win);
  s.uiDirty = true;  // hover highlights in the panel
  s.cursorX = x;
  s.cursorY = y;
  if (!s.dragging) {
    s.readoutWanted = true;
    return;
  }
  int width = 0, height = 0;
  windowSize(win, &width, &height);
  const double dx = x - s.lastX, dy = y - s.lastY;
  s.lastX = x;
  s.lastY = y;
  if (dx == 0.0 && dy == 0.0) return;
  userMoved(s);
  if (s.tilting) {
    engine::tiltAboutCentre(s.pose, s.fovYDeg, width, height, dx * kDegreesPerPixel, -dy * kDegreesPerPixel);
  } else if (s.grabbed) {
    engine::dragGroundPoint(s.pose, s.fovYDeg, width, height, *s.grabbed, x, y);  // false beyond the limb: stays
  } else {
    engine::orbitByPixels(s.pose, s.fovYDeg, height, dx, dy);
  }
}

void onScroll(GLFWwindow* win, double, double yoff) {
  auto& s = stateOf(win);
  if (engine::ViewerPanelGL::capturesMouse()) return;
  int width = 0, height = 0;
  windowSize(win, &width, &height);
  userMoved(s);
  engine::zoomTowardPixel(s.pose, s.fovYDeg, width, height, s.cursorX, s.cursorY, std::pow(0.8, yoff));
}

void onChar(GLFWwindow* win, unsigned int) { stateOf(win).uiDirty = true; }  // typing into the panel

void onKey(GLFWwindow* win, int key, int, int action, int mods) {
  auto& s = stateOf(win);
  s.uiDirty = true;
  if (action == GLFW_RELEASE || engine::ViewerPanelGL::capturesKeyboard()) return;
  const bool repeat = action == GLFW_REPEAT;
  const bool shift = (mods & GLFW_MOD_SHIFT) != 0;
  const bool ctrl = (mods & GLFW_MOD_CONTROL) != 0;
  int width = 0, height = 0;
  windowSize(win, &width, &height);
  auto pan = [&](double fx, double fy) {
    userMoved(s);
    engine::panByFraction(s.pose, s.fovYDeg, width, height, fx, fy);
  };
  auto tilt = [&](double dHeadingDeg, double dPitchDeg) {
    userMoved(s);
    engine::tiltAboutCentre(s.pose, s.fovYDeg, width, height, dHeadingDeg, dPitchDeg);
  };
  auto zoom = [&](double factor) {
    userMoved(s);
    engine::zoomTowardPixel(s.pose, s.fovYDeg, width, height, 0.5 * width, 0.5 * height, factor);
  };
  switch (key) {
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: glfwSetWindowShouldClose(win, GLFW_TRUE); break;
    case GLFW_KEY_R:
    case GLFW_KEY_H:
      if (!repeat) s.flyHome = true;
      break;
    case GLFW_KEY_P:
      if (!repeat) s.screenshotRequested = true;
      break;
    case GLFW_KEY_LEFT: shift ? tilt(-kKeyTurnDeg, 0.0) : pan(kPanFraction, 0.0); break;
    case GLFW_KEY_RIGHT: shift ? tilt(kKeyTurnDeg, 0.0) : pan(-kPanFraction, 0.0); break;
    case GLFW_KEY_A: pan(kPanFraction, 0.0); break;
    case GLFW_KEY_D: pan(-kPanFraction, 0.0); break;
    case GLFW_KEY_UP:
    case GLFW_KEY_W: pan(0.0, kPanFraction); break;
    case GLFW_KEY_S:
      if (ctrl) {
        if (!repeat) s.saveSceneRequested = true;
        break;
      }
      pan(0.0, -kPanFraction);
      break;
    case GLFW_KEY_DOWN: pan(0.0, -kPanFraction); break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: zoom(kKeyZoomFactor); break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: zoom(1.0 / kKeyZoomFactor); break;
    case GLFW_KEY_PAGE_UP: tilt(0.0, kKeyTiltDeg); break;
    case GLFW_KEY_PAGE_DOWN: tilt(0.0, -kKeyTiltDeg); break;
    case GLFW_KEY_PERIOD: s.timeMove += 1; break;
    case GLFW_KEY_COMMA: s.timeMove -= 1; break;
    case GLFW_KEY_HOME:
      if (!repeat) s.timeHome = true;
      break;
    case GLFW_KEY_SPACE:
      if (!repeat) s.playing = !s.playing;
      break;
    default: break;
  }
  s.dirty = true;
}

/// GLFW key codes of the script's key names (engine::scriptKeyNames()).
int glfwKeyOf(const std::string& name) {
  if (name.size() == 1 && name[0] >= 'A' && name[0] <= 'Z') return GLFW_KEY_A + (name[0] - 'A');
  if (name.size() == 1 && name[0] >= '0' && name[0] <= '9') return GLFW_KEY_0 + (name[0] - '0');
  static const std::map<std::string, int> keys = {
      {"Right", GLFW_KEY_RIGHT},         {"Left", GLFW_KEY_LEFT},      {"Up", GLFW_KEY_UP},
      {"Down", GLFW_KEY_DOWN},           {"PageUp", GLFW_KEY_PAGE_UP}, {"PageDown", GLFW_KEY_PAGE_DOWN},
      {"Home", GLFW_KEY_HOME},           {"End", GLFW_KEY_END},        {"Space", GLFW_KEY_SPACE},
      {"Enter", GLFW_KEY_ENTER},         {"Escape", GLFW_KEY_ESCAPE},  {"Tab", GLFW_KEY_TAB},
      {"Backspace", GLFW_KEY_BACKSPACE}, {"Plus", GLFW_KEY_KP_ADD},    {"Minus", GLFW_KEY_MINUS},
      {"Comma", GLFW_KEY_COMMA},         {"Period", GLFW_KEY_PERIOD}};
  const auto it = keys.find(name);
  return it == keys.end() ? GLFW_KEY_UNKNOWN : it->second;
}

/// The callbacks installed on the window now (the panel's backend, chaining to ours), which a
/// script calls exactly as GLFW would.
struct InstalledCallbacks {
  GLFWcursorposfun cursorPos = nullptr;
  GLFWmousebuttonfun mouseButton = nullptr;
  GLFWscrollfun scroll = nullptr;
  GLFWkeyfun key = nullptr;
  GLFWcharfun character = nullptr;
  GLFWcursorenterfun cursorEnter = nullptr;
  static InstalledCallbacks of(GLFWwindow* w) {
    InstalledCallbacks c;
    c.cursorPos = glfwSetCursorPosCallback(w, nullptr);
    glfwSetCursorPosCallback(w, c.cursorPos);
    c.mouseButton = glfwSetMouseButtonCallback(w, nullptr);
    glfwSetMouseButtonCallback(w, c.mouseButton);
    c.scroll = glfwSetScrollCallback(w, nullptr);
    glfwSetScrollCallback(w, c.scroll);
    c.key = glfwSetKeyCallback(w, nullptr);
    glfwSetKeyCallback(w, c.key);
    c.character = glfwSetCharCallback(w, nullptr);
    glfwSetCharCallback(w, c.character);
    c.cursorEnter = glfwSetCursorEnterCallback(w, nullptr);
    glfwSetCursorEnterCallback(w, c.cursorEnter);
    return c;
  }
};

/// A script as steps, one per frame; a step returns false to be run again next frame (waiting
/// for a flight to land).
struct ScriptRunner {
  std::string path;
  std::deque<std::pair<int, std::function<bool()>>> steps;  ///< (line, step)
  int line = 0;                                             ///< of the step running
};

/// UTF-8 bytes to code points (the character callback's unit); invalid bytes pass as themselves.
std::vector<unsigned int> codePoints(const std::string& text) {
  std::vector<unsigned int> out;
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    const int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
    unsigned int cp = extra == 0 ? c : (c & (0x3Fu >> extra));
    std::size_t j = 1;
    for (; j <= static_cast<std::size_t>(extra) && i + j < text.size(); ++j)
      cp = (cp << 6) | (static_cast<unsigned char>(text[i + j]) & 0x3Fu);
    out.push_back(cp);
    i += j;
  }
  return out;
}

/// The script's actions as steps through the window's installed callbacks (so the panel and the
/// viewer see them as they see a user's input), appended to `script`.
void addScriptSteps(ScriptRunner& script, const std::vector<engine::ScriptAction>& actions, GLFWwindow* w,
                    Interaction& state, engine::FlyToWindowState& flyState) {
  const InstalledCallbacks cb = InstalledCallbacks::of(w);
  auto add = [&](int line, std::function<bool()> step) { script.steps.emplace_back(line, std::move(step)); };
  auto move = [w, cb](double x, double y) {
    return [w, cb, x, y] {
      glfwSetCursorPos(w, x, y);  // the real pointer too: ImGui 1.86 polls it
      if (cb.cursorPos) cb.cursorPos(w, x, y);
      return true;
    };
  };
  auto button = [w, cb](int b, int action, int mods) {
    return [w, cb, b, action, mods] {
      if (cb.mouseButton) cb.mouseButton(w, b, action, mods);
      return true;
    };
  };
  add(0, [w, cb] {
    if (cb.cursorEnter) cb.cursorEnter(w, GLFW_TRUE);  // the pointer is in the window
    return true;
  });
  for (const engine::ScriptAction& a : actions) {
    using Kind = engine::ScriptAction::Kind;
    const int mods = (a.shift ? GLFW_MOD_SHIFT : 0) | (a.ctrl ? GLFW_MOD_CONTROL : 0);
    const int b = a.button == 0   ? GLFW_MOUSE_BUTTON_LEFT
                  : a.button == 1 ? GLFW_MOUSE_BUTTON_RIGHT
                                  : GLFW_MOUSE_BUTTON_MIDDLE;
    const auto& n = a.numbers;
    switch (a.kind) {
      case Kind::Camera:
        add(a.line, [&state, n] {
          engine::CameraPose p{n[0],
                               globe::wrapLongitudeDeg(n[1]),
                               n[2],
                               n.size() > 3 ? n[3] : 0.0,
                               n.size() > 4 ? n[4] : -90.0,
                               n.size() > 5 ? n[5] : 0.0};
          state.pose = p;
          userMoved(state);
          return true;
        });
        break;
      case Kind::Move: add(a.line, move(n[0], n[1])); break;
      case Kind::Down: add(a.line, button(b, GLFW_PRESS, mods)); break;
      case Kind::Up: add(a.line, button(b, GLFW_RELEASE, mods)); break;
      case Kind::Click:
        add(a.line, move(n[0], n[1]));
        add(a.line, button(b, GLFW_PRESS, mods));
        add(a.line, button(b, GLFW_RELEASE, mods));
        break;
      case Kind::Drag: {
        const int steps = n.size() > 4 ? static_cast<int>(n[4]) : 8;
        add(a.line, move(n[0], n[1]));
        add(a.line, button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, mods));
        for (int k = 1; k <= steps; ++k)
          add(a.line, move(n[0] + (n[2] - n[0]) * k / steps, n[1] + (n[3] - n[1]) * k / steps));
        add(a.line, button(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, mods));
        break;
      }
      case Kind::Wheel:
        add(a.line, move(n[0], n[1]));
        add(a.line, [w, cb, clicks = n[2]] {
          if (cb.scroll) cb.scroll(w, 0.0, clicks);
          return true;
        });
        break;
      case Kind::Key: {
        const int key = glfwKeyOf(a.text);
        add(a.line, [w, cb, key, mods] {
          if (cb.key) cb.key(w, key, glfwGetKeyScancode(key), GLFW_PRESS, mods);
          return true;
        });
        add(a.line, [w, cb, key, mods] {
          if (cb.key) cb.key(w, key, glfwGetKeyScancode(key), GLFW_RELEASE, mods);
          return true;
        });
        break;
      }
      case Kind::Type:
        add(a.line, [w, cb, chars = codePoints(a.text)] {
          if (cb.character)
            for (unsigned int c : chars) cb.character(w, c);
          return true;
        });
        break;
      case Kind::Wait:
        for (int k = 0; k < static_cast<int>(n[0]); ++k) add(a.line, [] { return true; });
        break;
      case Kind::FlyTo:
        add(a.line, [&flyState, name = a.text] {
          std::snprintf(flyState.query, sizeof flyState.query, "%s", name.c_str());
          flyState.requested = true;
          return true;
        });
        add(a.line, [&state, &flyState] { return !flyState.requested && !state.flight; });
        break;
      case Kind::Readout:
        add(a.line, [&state] {
          state.readoutWanted = true;
          return true;
        });
        break;
      case Kind::Screenshot:
        add(a.line, [&state, file = a.text] {
          state.screenshotPath = file;
          state.screenshotRequested = true;
          return true;
        });
        break;
    }
  }
}

/// Names to fly to: the scene's radars and markers, the NEXRAD sites ($ATMOGLOBE_NEXRAD_SITES or the built-in
/// table), tzdata's cities.
engine::Gazetteer buildGazetteer(const engine::SceneRendererGL& renderer, const std::vector<engine::Marker>& markers,
                                 const std::vector<engine::DeferredRadar>& deferred) {
  constexpr double kRadarViewMeters = 4e5;  // the 230 km of a radar's range in a 60 deg view
  constexpr double kMarkerViewMeters = 2e5;
  constexpr double kPlaceViewMeters = 1e5;
  engine::Gazetteer g;
  // A place to fly to is a radar's site, by its names (site, label), loaded or not yet.
  auto addRadar = [&](const std::string& site, const std::string& label, double latDeg, double lonDeg) {
    engine::Place p;
    for (const std::string& n : {site, label})
      if (!n.empty()) p.names.push_back(n);
    if (p.names.empty()) p.names.push_back("radar");
    p.kind = "radar";
    p.latDeg = latDeg;
    p.lonDeg = globe::wrapLongitudeDeg(lonDeg);
    p.viewHeightMeters = kRadarViewMeters;
    g.add(std::move(p));
  };
  for (std::size_t i = 0; i < renderer.volumeLayerCount(); ++i) {
    if (const auto* r = renderer.layerAs<engine::RadarSourceGL>(i)) {
      const volume::GeolocationSite& site = r->radarVolume().polar().site;
      addRadar(r->siteName(), r->siteMarker()->label, site.latDeg, site.lonDeg);
    }
  }
  for (const engine::DeferredRadar& d : deferred)  // not loaded yet: flying there loads them
    addRadar(d.footprint.siteName, d.description.label, d.footprint.latDeg, d.footprint.lonDeg);
  for (const engine::Marker& m : markers) {
    if (m.label.empty()) continue;
    g.add(engine::Place{{m.label}, "marker", m.latDeg, m.lonDeg, kMarkerViewMeters});
  }
  // Every WSR-88D site: the user's list ($ATMOGLOBE_NEXRAD_SITES) if given, else the built-in table.
  if (const char* sites = std::getenv("ATMOGLOBE_NEXRAD_SITES"); sites && *sites) {
    if (auto s = g.addStationList(sites, "NEXRAD site", kRadarViewMeters); !s)
      std::cerr << "atmoglobe view: fly-to names: " << s.error() << " (NEXRAD sites left out)\n";
  } else {
    g.addStations(volume::builtinNexradSites(), "NEXRAD site", kRadarViewMeters);
  }
  if (std::filesystem::exists(engine::kZoneTabPath)) {
    if (auto s = g.addZoneTab(engine::kZoneTabPath, kPlaceViewMeters); !s)
      std::cerr << "atmoglobe view: fly-to names: " << s.error() << "\n";
  }
  return g;
}

std::string describe(const engine::Place& p) {
  char where[64];
  std::snprintf(where, sizeof where, " at %.4f, %.4f", p.latDeg, p.lonDeg);
  return p.names.front() + " (" + p.kind + ")" + where;
}

int runView(const ViewOptions& o) {
  // A bad script is reported before any window opens.
  std::vector<engine::ScriptAction> actions;
  if (!o.script.empty()) {
    auto parsed = engine::readViewerScript(o.script);
    if (!parsed) return fail("view", parsed.error());
    actions = std::move(*parsed);
  }
  auto scene = resolveScene(o.scene);
  if (!scene) return fail("view", scene.error());
  // Networks seen from far away drawn from their far field unless the scene or --far-field says off.
  engine::setUnsetFarField(*scene, engine::FarField::Auto);
  auto window = engine::WindowGL::create(scene->widthPx, scene->heightPx, "atmoglobe");
  if (!window) return fail("view", window.error());
  auto loader = engine::openImagery(scene->imagery, {});
  if (!loader) return fail("view", loader.error());
  auto renderer = engine::SceneRendererGL::create(*loader);
  if (!renderer) return fail("view", renderer.error());
  std::vector<engine::Marker> markers = scene->markers;
  // Radars the first view does not show wait until the camera may see them (sphereMayBeVisible
  // each frame at rest): a network scene opens at the cost of the radars in view.
  std::vector<engine::DeferredRadar> deferred;
  if (!o.loadAll) {
    const engine::Camera first(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
    const std::size_t radars = static_cast<std::size_t>(
        std::count_if(scene->volumes.begin(), scene->volumes.end(),
                      [](const engine::VolumeLayerDescription& d) { return d.kind == engine::VolumeKind::Radar; }));
    deferred = engine::deferRadarsOutsideView(*scene, first);
    if (!deferred.empty())
      std::cerr << "atmoglobe view: " << deferred.size() << " of " << radars
                << " radars outside the view, loaded when they come into view (--load-all loads them now)\n";
  }
  // An input that fails is reported and left out; the rest is shown (as `render` does).
  std::vector<std::string> inputErrors;
  if (auto s = populateScene(**renderer, *scene, &markers, &inputErrors); !s) return fail("view", s.error());
  for (const std::string& e : inputErrors) std::cerr << "atmoglobe view: error: " << e << "\n";
  const engine::Gazetteer gazetteer = buildGazetteer(**renderer, markers, deferred);

  Interaction state;
  state.pose = state.initial = scene->camera;
  state.fovYDeg = scene->fovYDeg;
  state.scripted = !o.script.empty();
  if (!o.flyTo.empty()) {
    auto place = gazetteer.find(o.flyTo);
    if (!place) return fail("view", place.error());
    state.pose = engine::viewOfPlace(*place);
    std::cout << "fly to: " << describe(*place) << std::endl;
  }
  GLFWwindow* w = (*window)->handle();
  glfwSetWindowUserPointer(w, &state);
  glfwSetMouseButtonCallback(w, onMouseButton);
  glfwSetCursorPosCallback(w, onCursorPos);
  glfwSetScrollCallback(w, onScroll);
  glfwSetKeyCallback(w, onKey);
  glfwSetCharCallback(w, onChar);

  // The scene's time axis, when a grid has several steps or a radar is a loop (time keys and playing).
  TimeCursor time;
  if (!scene->volumes.empty()) time.start(**renderer, o.timeSubsteps, !o.noPrefetch);
  state.playing = o.play && time.axis;
  auto showTime = [&](long position) -> Status {
    auto when = time.moveTo(**renderer, position);
    if (!when) return when.forwardError();
    if (!*when) return Ok{};
    glfwSetWindowTitle(w, ("atmoglobe  " + **when).c_str());
    std::cout << "time: " << **when << std::endl;
    return Ok{};
  };

  // The control panel, after the window's own callbacks (its backend chains to them).
  std::unique_ptr<engine::ViewerPanelGL> panel;
  if (!o.noPanel) {
    auto p = engine::ViewerPanelGL::create(w);
    if (!p) return fail("view", p.error());
    panel = std::move(*p);
  }
  engine::FlyToWindowState flyState;
  engine::ViewerPanelState panelState;
  double playSeconds = o.playSeconds;  ///< the loop speed; the panel may change it
  panelState.extraWindows = [&flyState, scripted = state.scripted] {
    engine::drawFlyToWindow(flyState);
    if (scripted) engine::drawPointerMark();  // no system cursor in a scripted screenshot
  };
  panelState.scene = renderer->get();  // the panel edits the layers live
  auto listLayer = [&](const engine::VolumeSourceGL& layer) {
    panelState.layers.push_back(layer.title() + " (" +
                                std::filesystem::path(layer.description().path).filename().string() + ")");
  };
  for (std::size_t i = 0; i < (*renderer)->volumeLayerCount(); ++i) listLayer((*renderer)->layer(i));
  // Deferred radars `camera` may see, loaded now (on the GL thread: the frame waits for them).
  // A loop or a timed volume joins the scene's time axis, which keeps the time shown.
  auto loadComingIntoView = [&](const engine::Camera& camera) {
    bool added = false;
    for (auto it = deferred.begin(); it != deferred.end();) {
      if (!engine::sphereMayBeVisible(camera, it->footprint.sphere)) {
        ++it;
        continue;
      }
      const double t0 = glfwGetTime();
      auto layer = (*renderer)->addVolume(it->description);
      if (!layer) {
        std::cerr << "atmoglobe view: error: " << engine::layerOrigin({it->origin}, 0, "--radar") << ": "
                  << layer.error() << std::endl;
      } else {
        char took[48];
        std::snprintf(took, sizeof took, " (came into view, loaded in %.0f ms)", 1000.0 * (glfwGetTime() - t0));
        std::cout << "loaded: " << (*layer)->title() << took << std::endl;
        std::cerr << "atmoglobe view: " << (*layer)->loadNote() << "\n";
        listLayer(**layer);
        scene->volumes.push_back(it->description);
        scene->origins.volumes.push_back(it->origin);
        added = true;
      }
      it = deferred.erase(it);
    }
    if (!added) return;
    state.dirty = true;
    // The axis again, over every layer now; back at the time shown before when it is still on it.
    const std::string shown = time.label;
    std::vector<double> stalls = std::move(time.stallMs);
    time = TimeCursor{};
    time.start(**renderer, o.timeSubsteps, !o.noPrefetch);
    time.stallMs = std::move(stalls);
    if (time.axis && !shown.empty()) {
      const auto& times = time.axis->times;
      if (auto at = std::find(times.begin(), times.end(), shown); at != times.end()) {
        time.position = -1;  // moveTo shows the step even when the position is the same
        if (auto st = showTime(static_cast<long>(at - times.begin()) * time.substeps); !st)
          std::cerr << "atmoglobe view: error: " << st.error() << std::endl;
      }
    }
  };
  double frameMs = 0.0;
  engine::MovingImageScale pacing;
  double lastMovingScale = engine::VolumeRendererGL::kPreviewScale;
  engine::FrameTimeSummary frameTimes;
  // A line per scene drawn: how long it took, and whether the camera was moving (volumes at the
  // moving image scale) - the viewer's frame times, measured where it runs.
  std::ofstream frameLog;
  if (!o.frameLog.empty()) {
    frameLog.open(o.frameLog);
    if (!frameLog) return fail("view", "--frame-log " + o.frameLog + ": cannot open for writing");
    frameLog << "frame,moving,volume_image_scale,width,height,scene_ms,volumes_complete\n";
  }

  // A fly-to asked for by the box (Enter or Fly), or by a script's flyto through the same state.
  auto handleFlyRequest = [&]() -> Status {
    if (!flyState.requested) return Ok{};
    flyState.requested = false;
    auto place = gazetteer.find(flyState.query);
    if (!place) {
      flyState.message = place.error();
      std::cout << "fly to: " << place.error() << std::endl;
      return place.forwardError();
    }
    flyState.message = "to " + describe(*place);
    std::cout << "fly to: " << describe(*place) << std::endl;
    startFlight(state, engine::viewOfPlace(*place));
    return Ok{};
  };

  // The script as steps through the installed callbacks.
  ScriptRunner script;
  script.path = o.script;
  if (state.scripted) addScriptSteps(script, actions, w, state, flyState);
  std::vector<std::string> lastPrintedReadout;
  std::optional<engine::CameraPose> readoutPose;  ///< the camera of the last readout
  auto updateReadout = [&](const engine::FramebufferGL& target) {
    const auto& p = state.pose;
    if (!readoutPose || readoutPose->latDeg != p.latDeg || readoutPose->lonDeg != p.lonDeg ||
        readoutPose->heightMeters != p.heightMeters || readoutPose->headingDeg != p.headingDeg ||
        readoutPose->pitchDeg != p.pitchDeg)
      state.readoutWanted = true;  // the camera moved under a resting pointer
    if (!state.readoutWanted || state.dragging || engine::ViewerPanelGL::capturesMouse()) return;
    if (!panel && !state.scripted) return;
    state.readoutWanted = false;
    readoutPose = state.pose;
    int ww = 0, wh = 0;
    glfwGetWindowSize(w, &ww, &wh);
    // Window coordinates to framebuffer pixels (they differ on high-DPI screens).
    const double sx = ww > 0 ? static_cast<double>(target.widthPx()) / ww : 1.0;
    const double sy = wh > 0 ? static_cast<double>(target.heightPx()) / wh : 1.0;
    const engine::Camera camera(state.pose, state.fovYDeg, target.widthPx(), target.heightPx());
    panelState.readout = engine::readoutAt(**renderer, camera, state.cursorX * sx, state.cursorY * sy).lines;
    state.uiDirty = true;
    if (state.scripted && panelState.readout != lastPrintedReadout) {
      char at[64];
      std::snprintf(at, sizeof at, "readout at pixel %.1f, %.1f", state.cursorX, state.cursorY);
      std::cout << at << std::endl;
      for (const std::string& line : panelState.readout) std::cout << "readout: " << line << std::endl;
      lastPrintedReadout = panelState.readout;
    }
  };
  auto drawPanel = [&](const engine::Camera* camera) {
    if (!panel) return;
    state.uiDirty = false;
    panelState.timePositions = time.axis ? static_cast<int>(time.count()) : 0;
    panelState.timePosition = static_cast<int>(time.position);
    panelState.timeLabel = time.label;
    panelState.playing = state.playing;
    panelState.playSeconds = static_cast<float>(playSeconds);
    panelState.frameMilliseconds = frameMs;
    if (camera) panelState.legend = (*renderer)->legendFor(*camera);
    const int before = panelState.timePosition;
    if (panel->draw(panelState)) {
      state.timeMove += panelState.timePosition - before;
      state.playing = panelState.playing;
      playSeconds = panelState.playSeconds;
      state.dirty = true;
    }
    if (panelState.screenshotRequested) {
      panelState.screenshotRequested = false;
      state.screenshotRequested = true;
      state.dirty = true;
    }
    if (panelState.saveSceneRequested) {
      panelState.saveSceneRequested = false;
      state.saveSceneRequested = true;
    }
  };

  std::unique_ptr<engine::FramebufferGL> target;
  int frame = 0;
  int framesAfterScript = 0;
  bool wasMoving = false;
  const bool batch = o.frames > 0 || state.scripted;
  while (!glfwWindowShouldClose(w)) {
    if (state.flyHome) {
      state.flyHome = false;
      startFlight(state, state.initial);
    }
    // The frame that ends a flight is still a moving one: the first frame at rest then has the
    // same camera as the last moving frame, whose quarter-resolution image is the refinement's
    // preview (VolumeRendererGL::drawProgressive).
    const bool flying = state.flight.has_value();
    if (state.flight) {
      const double t = (clockSeconds(state) - state.flight->startSeconds) / state.flight->seconds;
      state.pose = engine::flightPose(state.flight->from, state.flight->to, t);
      touched(state);
      if (t >= 1.0) state.flight.reset();
    }
    // A script's run is deterministic: full quality except while flying.
    const bool moving = state.scripted ? flying : glfwGetTime() - state.lastInputSeconds < kSettleSeconds;
    if (!batch && !state.dirty && !moving && !wasMoving && !state.playing && !state.screenshotRequested &&
        (*renderer)->globe().lastFrameComplete() && (*renderer)->volumesComplete()) {
      if (target) updateReadout(*target);
      if (state.uiDirty && panel && target) {
        // Only the panel changed: the last picture again with the panel over it.
        glBlitNamedFramebuffer(target->id(), 0, 0, 0, target->widthPx(), target->heightPx(), 0, 0, target->widthPx(),
                               target->heightPx(), GL_COLOR_BUFFER_BIT, GL_NEAREST);
        drawPanel(nullptr);
        glfwSwapBuffers(w);
      }
      if (auto s = handleFlyRequest(); !s) {
        // Shown in the box; the viewer goes on.
      }
      glfwWaitEventsTimeout(0.1);  // nothing to redraw: sleep until input
      continue;
    }
    glfwPollEvents();
    if (state.scripted && target) {
      if (!script.steps.empty()) {
        script.line = script.steps.front().first;
        if (script.steps.front().second()) script.steps.pop_front();
      } else {
        ++framesAfterScript;
      }
      state.scriptSeconds += kScriptFrameSeconds;
    }
    if (time.axis) {
      long wanted = time.position + state.timeMove;
      if (state.timeHome) wanted = 0;
      const double now = glfwGetTime();
      if (state.playing && (batch || now - time.lastAdvanceSeconds >= playSeconds)) {
        wanted += 1;
        time.lastAdvanceSeconds = now;
      }
      state.timeMove = 0;
      state.timeHome = false;
      if (auto st = showTime(wanted); !st) return fail("view", st.error());
    }
    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(w, &fbw, &fbh);
    if (fbw < 1 || fbh < 1) continue;
    const bool resized = !target || target->widthPx() != fbw || target->heightPx() != fbh;
    if (resized) {
      auto t = engine::FramebufferGL::create(fbw, fbh);
      if (!t) return fail("view", t.error());
      target = std::move(*t);
    }
    const engine::Camera camera(state.pose, state.fovYDeg, fbw, fbh);
    if (!deferred.empty() && !moving) loadComingIntoView(camera);
    // A script redraws the scene only when something changed (else the last picture with the
    // panel over it); everything else draws every frame it gets here.
    const bool sceneNeeded = !state.scripted || resized || state.dirty || moving || wasMoving || state.playing ||
                             !(*renderer)->globe().lastFrameComplete() || !(*renderer)->map().lastFrameComplete() ||
                             !(*renderer)->volumesComplete();
    if (sceneNeeded) {
      // At rest with nothing changed since the last frame (no input, edit, time step or motion):
      // only the volumes are still refining, so the frame may start from the last one's
      // background instead of drawing the globe and map lines again.
      (*renderer)->setBackgroundReuse(!state.dirty && !moving && !wasMoving && !state.playing && !resized &&
                                      !state.screenshotRequested);
      // A motion's first frame: the scale the last view's full-quality march says meets the target.
      if (moving && !wasMoving) pacing.seedFromFullMarch((*renderer)->volumeRenderer().fullMarchEstimateMs());
      const double movingScale = o.movingScale > 0.0 ? o.movingScale : pacing.scale();
      if (moving) lastMovingScale = movingScale;
      for (std::size_t i = 0; i < (*renderer)->volumeLayerCount(); ++i) {
        engine::VolumeSourceGL& layer = (*renderer)->layer(i);
        const double full = layer.description().imageScale;  // the panel may change it
        layer.options().imageScale = moving ? std::min(full, movingScale) : full;
        // A moving frame is the small image alone (its cost is what the pacing measures);
        // adaptive refinement, if the layer asks for it, refines the picture at rest.
        layer.options().refineThreshold = moving ? -1.0 : layer.description().refineThreshold;
      }
      wasMoving = moving;
      state.dirty = false;
      // A screenshot shows the finished picture: that frame is drawn whole.
      const double refineMs = o.refineMs >= 0.0 ? o.refineMs : (batch ? 0.0 : kRefineBudgetMs);
      (*renderer)->setProgressiveBudget(moving || state.screenshotRequested ? 0.0 : refineMs);
      // Grids' coarser copies are made on a worker while frames go on, except for a screenshot
      // (the same picture as `render`) and --frames runs.
      const bool interactiveFrame = !state.screenshotRequested && o.frames <= 0;
      (*renderer)->setDetailInBackground(interactiveFrame);
      // Coastlines and borders of a new level or newly in view: read and built within a few
      // milliseconds a frame, the level before drawn meanwhile (a flight across a level took
      // 84 ms in one frame without it); whole for a screenshot and --frames runs.
      (*renderer)->map().setBuildBudgetMs(interactiveFrame ? kMapBuildBudgetMs : 0.0);
      (*renderer)->volumeRenderer().setFarFieldBuildBudgetMs(interactiveFrame ? kFarFieldBuildBudgetMs : 0.0);
      // The first frame at rest takes the last moving frame's volume image as its preview.
      (*renderer)->volumeRenderer().setPreviewScale(lastMovingScale);
      // Our own target has a float depth buffer (reverse-Z); the window's may not.
      const double t0 = glfwGetTime();
      (*renderer)->renderFrame(camera, markers, *target);
      glFinish();
      frameMs = 1000.0 * (glfwGetTime() - t0);
      if (moving) pacing.reportMovingFrame(frameMs);
      if (frame > 0) frameTimes.add(moving, frameMs);  // the first frame compiles shaders and loads
      if (frameLog.is_open()) {
        const double scale = (*renderer)->volumeLayerCount() > 0 ? (*renderer)->layer(0).options().imageScale : 1.0;
        frameLog << frame << "," << (moving ? 1 : 0) << "," << scale << "," << fbw << "," << fbh << "," << frameMs
                 << "," << ((*renderer)->volumesComplete() ? 1 : 0) << "\n";
        frameLog.flush();
      }
    }
    glBlitNamedFramebuffer(target->id(), 0, 0, 0, fbw, fbh, 0, 0, fbw, fbh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    drawPanel(&camera);
    if (auto s = handleFlyRequest(); !s && state.scripted) {
      return fail("view", script.path + " line " + std::to_string(script.line) + ": " + s.error());
    }
    if (!moving) updateReadout(*target);  // not mid-flight: the place under the pointer keeps changing
    ++frame;
    const bool last = state.scripted ? script.steps.empty() && framesAfterScript >= std::max(o.frames, 1)
                                     : o.frames > 0 && frame >= o.frames;
    std::vector<std::string> shots;
    if (state.screenshotRequested) {
      shots.push_back(!state.screenshotPath.empty()
                          ? state.screenshotPath
                          : "atmoglobe-screenshot-" + std::to_string(++state.screenshotCount) + ".png");
      state.screenshotRequested = false;
      state.screenshotPath.clear();
    }
    if (last && !o.screenshot.empty()) shots.push_back(o.screenshot);
    if (!shots.empty()) {
      // What the user sees: the scene with the panel over it.
      const globe::ImageRGBA8 shot = panel ? engine::readWindowColorGL(fbw, fbh) : target->readColor();
      for (const std::string& path : shots) {
        if (auto s = globe::writePng(path, shot); !s) {
          if (state.scripted && !last)
            return fail("view", script.path + " line " + std::to_string(script.line) + ": " + s.error());
          return fail("view", s.error());
        }
        std::cout << "screenshot: " << path << std::endl;
      }
    }
    if (state.saveSceneRequested) {
      state.saveSceneRequested = false;
      // What is on the screen as a scene: the layers as edited, each grid at the step shown, the
      // camera, field of view, size and exaggeration of this frame (engine::sceneToJson).
      engine::SceneDescription saved = *scene;
      saved.camera = state.pose;
      saved.fovYDeg = state.fovYDeg;
      saved.widthPx = fbw;
      saved.heightPx = fbh;
      saved.verticalExaggeration = (*renderer)->verticalExaggeration();
      saved.volumes.clear();
      for (std::size_t i : (*renderer)->volumeOrder()) {
        const engine::VolumeSourceGL& layer = (*renderer)->layer(i);
        engine::VolumeLayerDescription d = layer.description();
        if (d.kind == engine::VolumeKind::Grid) {
          if (auto times = layer.times(); times && layer.step() < times->size() && !(*times)[layer.step()].empty())
            d.time = (*times)[layer.step()];
          // A grid's colours span the values of the step loaded first; loaded at another step the
          // saved scene would span that step's: keep the span shown (the table's ends, field units).
          const volume::ColorTable& table = layer.options().render.transfer.colors;
          if (!d.settings.valueRange && table.stops().size() >= 2)
            d.settings.valueRange = glm::dvec2((table.stops().front().value - table.offset()) / table.scale(),
                                               (table.stops().back().value - table.offset()) / table.scale());
        }
        saved.volumes.push_back(std::move(d));
      }
      for (const engine::DeferredRadar& d : deferred) saved.volumes.push_back(d.description);  // not seen yet
      saved.surfaces.clear();  // the maps as edited in the panel
      for (const auto& surface : (*renderer)->surfaces()) saved.surfaces.push_back(surface->description());
      if (auto st = globe::writeFileAtomic(o.saveScene, engine::sceneToJson(saved)); !st) {
        std::cerr << "atmoglobe view: error: " << st.error() << std::endl;
        if (state.scripted) return fail("view", st.error());
      } else {
        std::cout << "scene saved: " << o.saveScene << std::endl;
      }
    }
    glfwSwapBuffers(w);
    if (last) break;
    if (batch) (*loader)->waitIdle();  // scripted runs: let imagery arrive between frames
  }
  if (!time.stallMs.empty()) std::cerr << engine::stallSummary(time.stallMs, time.prefetch != nullptr) << "\n";
  // A scripted or logged run reports its frame times (the scene's draw, up to glFinish).
  if ((state.scripted || frameLog.is_open()) && !frameTimes.text().empty())
    std::cout << "frame times (scene draw, first frame left out): " << frameTimes.text() << std::endl;
  return 0;
}
}  // namespace

Command addViewCommand(CLI::App& root) {
  auto options = std::make_shared<ViewOptions>();
  CLI::App* c = root.add_subcommand("view", "Open the desktop globe viewer (needs a display; e.g. xvfb-run -a)");
  addSceneOptions(*c, options->scene);
  c->add_option("--frames", options->frames,
                "Quit after this many frames (with --script: frames drawn after the script, default 1)");
  c->add_option("--screenshot", options->screenshot, "With --frames or --script: save the last frame to this PNG");
  c->add_option("--time-substeps", options->timeSubsteps,
                "Time positions per grid time step: between steps the grids are interpolated linearly in time")
      ->capture_default_str();
  c->add_option("--play-seconds", options->playSeconds, "Seconds per time position while playing")
      ->capture_default_str();
  c->add_flag("--play", options->play, "Start playing the time steps (with --frames: one position per frame)");
  c->add_option("--save-scene", options->saveScene,
                "Where Ctrl+S and the panel's \"Save scene\" write the scene shown (layers as edited, camera, time)")
      ->capture_default_str();
  c->add_flag(
      "--load-all", options->loadAll,
      "Load every radar at start (by default a radar outside the first view is loaded when it comes into view)");
  c->add_flag("--no-panel", options->noPanel, "No control panel (time slider, layers, frame time, screenshot)");
  c->add_option("--script", options->script,
                "Replay this file of viewer actions (mouse, wheel, keys, text, camera, waits, flyto, readout, "
                "screenshot; see engine/ViewerScript.h and the README), then quit");
  c->add_option(
      "--fly-to", options->flyTo,
      "Start above this radar, marker, NEXRAD site (built in, or $ATMOGLOBE_NEXRAD_SITES), place (tzdata's cities) or "
      "LAT,LON[,HEIGHT]");
  c->add_option("--frame-log", options->frameLog,
                "Write a CSV line per frame drawn: frame, moving (volumes at the moving image scale), volume "
                "image scale, size, milliseconds");
  c->add_option("--refine-ms", options->refineMs,
                "At rest, march the full-quality volumes in tiles for at most this long a frame, refining over "
                "frames (default 20; 0: whole frames; scripts and --frames runs draw whole frames unless given)")
      ->check(CLI::Range(0.0, 10000.0));
  c->add_option("--moving-scale", options->movingScale,
                "While the camera moves, march the volumes at this image scale (0.05..1; default: paced, at most 0.25 "
                "and less where frames would take over 40 ms)")
      ->check(CLI::Range(0.05, 1.0));
  c->add_flag("--no-prefetch", options->noPrefetch,
              "Read each time step when it is shown instead of ahead on a worker thread (for comparison)");
  c->footer(
      "Mouse: drag to grab and turn the globe, wheel to zoom toward the cursor, shift+drag or right-drag to tilt/turn.\n"
      "Keys: arrows/WASD move, +/- zoom, PageUp/PageDown tilt, shift+Left/Right turn, H or R fly home;\n"
      "      . / , next/previous time step, Space play/pause, Home first step, P screenshot, Esc/Q quit.");
  return {c, [options] { return runView(*options); }};
}

}  // namespace atmoglobe::tools
