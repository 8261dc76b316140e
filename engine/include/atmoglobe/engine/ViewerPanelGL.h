#pragma once
// The viewer's control panel (Dear ImGui, Debian libimgui-dev, with its GLFW and OpenGL 3
// backends) drawn over the window after the scene: the time slider (step, play, interpolated
// substeps); per volume layer (with ViewerPanelState::scene set) on/off, draw order, field,
// colour table, a transfer-function editor (opacity control points over a histogram of the
// field's values: volume/OpacityEditor.h, volume/ValueHistogram.h), mode and iso value, quality
// knobs (step, image scale, interpolation, beam model, classification), crop box; the scene's
// vertical exaggeration; what is loaded (CPU and GPU bytes per layer); colour keys, the readout,
// the frame time, the screenshot button; and a scale bar over the picture (Legend.h's
// scaleBarFor, the bar rendered PNGs carry). Edits go to the SceneRendererGL at once
// (setVolumeDescription, setVolumeOrder, changeVerticalExaggeration) and
// draw() returns true so the viewer redraws. docs/viewer-panel.md describes it.
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

class SceneRendererGL;

/// What the panel shows and what the user changed in it this frame.
struct ViewerPanelState {
  int timePositions = 0;            ///< positions on the time axis (0: no axis; the slider is hidden)
  int timePosition = 0;             ///< in/out: the slider
  std::string timeLabel;            ///< valid time shown (UTC)
  bool playing = false;             ///< in/out
  float playSeconds = 0.5f;         ///< in/out: seconds per time position while playing (loop speed)
  std::vector<std::string> layers;  ///< one line per layer (what is loaded)
  double frameMilliseconds = 0.0;
  std::vector<std::string> readout;    ///< the value under the cursor (Readout.h), one line each
  FrameLegend legend;                  ///< what the frame shows (SceneRendererGL::legendFor): times, keys
  bool screenshotRequested = false;    ///< out: the Screenshot button was pressed
  bool saveSceneRequested = false;     ///< out: the "Save scene" button was pressed
  std::function<void()> extraWindows;  ///< more ImGui windows drawn in the panel's frame (the fly-to box)
  /// The scene the layer controls edit (not owned); null: the layers are listed (`layers`) only.
  SceneRendererGL* scene = nullptr;
  bool scaleBar = true;  ///< draw the scale bar (legend.metersPerPixel) bottom left
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
  ViewerPanelGL();
  struct Editing;  ///< what the panel remembers between frames (pending crop boxes, histograms, drags)
  std::unique_ptr<Editing> editing_;
  bool drawLayers(SceneRendererGL& scene);
  bool drawSurfaces(SceneRendererGL& scene);  ///< the maps on the globe (SurfaceFieldGL): settings, member, statistic
};

}  // namespace atmoglobe::engine
