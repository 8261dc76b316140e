#pragma once
// The viewer's "Fly to" box: a small Dear ImGui window with a text field and
// a button, drawn inside the control panel's ImGui frame (ViewerPanelState::extraWindows). Enter
// or the button asks for a flight; the viewer looks the text up (Gazetteer.h) and reports back.
#include <string>

namespace atmoglobe::engine {

struct FlyToWindowState {
  char query[128] = {};    ///< the text field
  bool requested = false;  ///< out: Enter or "Fly" pressed with `query` filled in
  std::string message;     ///< shown under the field: where the flight goes, or why it cannot
};

/// Draws the window at the bottom right of the display (clear of the panel, top left). Call only inside an ImGui frame.
void drawFlyToWindow(FlyToWindowState& state);

}  // namespace atmoglobe::engine

namespace atmoglobe::engine {
/// A crosshair where ImGui sees the pointer: scripted screenshots carry no system cursor, so this
/// shows which place the readout is of. Call only inside an ImGui frame.
void drawPointerMark();
}  // namespace atmoglobe::engine
