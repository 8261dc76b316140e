#pragma once
// The viewer's control panel (Dear ImGui, Debian libimgui-dev, with its GLFW and OpenGL 3
// backends) drawn over the window after the scene. For now it holds what the viewer already
// does: the time slider (step, play, interpolated substeps), the layers and the frame time; the
// rest of the panel (transfer-function editor, per-layer settings) builds on it.
//
// Input: the backends chain to the window's own GLFW callbacks; while the pointer is over the
// panel (capturesMouse) or a widget has the keyboard (capturesKeyboard) the viewer leaves those
// events to it.
#include <atmoglobe/engine/Legend.h>
#include <atmoglobe/globe/Result.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

struct GLFWwindow;

namespace atmoglobe::engine {

/// What the panel shows and what the user changed in it this frame.
struct ViewerPanelState {
  int timePositions = 0;            ///< positions on the time axis (0: no axis; the slider is hidden)
  int timePosition = 0;             ///< in/out: the slider
  std::string timeLabel;            ///< valid time shown (UTC)
  bool playing = false;             ///< in/out
  std::vector<std::string> layers;  ///< one line per layer (what is loaded)
  double frameMilliseconds = 0.0;
  std::vector<std::string> readout;    ///< the value under the cursor (Readout.h), one line each
  FrameLegend legend;                  ///< what the frame shows (SceneRendererGL::legendFor): times, keys
  bool screenshotRequested = false;    ///< out: the Screenshot button was pressed
  std::function<void()> extraWindows;  ///< more ImGui windows drawn in the panel's frame (the fly-to box)
};

class ViewerPanelGL {
 public:
  /// Sets up ImGui for `window` (its GL context current) after the window's own callbacks are
  /// installed. The UI font is DejaVu Sans when installed (fonts-dejavu-core), else ImGui's own.
  static Result<std::unique_ptr<ViewerPanelGL>> create(GLFWwindow* window);
  ~ViewerPanelGL();
  ViewerPanelGL(const ViewerPanelGL&) = delete;
  ViewerPanelGL& operator=(const ViewerPanelGL&) = delete;

  /// Builds and draws the panel into the default framebuffer; returns true when the state changed.
  bool draw(ViewerPanelState& state);
  static bool capturesMouse();
  static bool capturesKeyboard();

 private:
  ViewerPanelGL() = default;
};

}  // namespace atmoglobe::engine
