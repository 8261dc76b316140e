#pragma once
// `atmoglobe view --script FILE`: a text file of viewer actions the viewer
// replays through the same GLFW callbacks as real input (tools/ViewCommand.cpp). GL-free parsing,
// so tests check it without a window. One action per line; blank lines and lines starting with
// '#' are skipped; words are separated by blanks. Pixels are window pixels from the top left.
//
//   camera LAT LON HEIGHT [HEADING PITCH [ROLL]]  jump the camera there (degrees, m)
//   move X Y                      move the pointer to (X, Y)
//   down [left|right|middle] [shift] [ctrl]       press a mouse button at the pointer
//   up [left|right|middle]        release it
//   click X Y [left|right|middle] move there, press and release
//   drag X0 Y0 X1 Y1 [STEPS] [shift] [ctrl]      press at (X0, Y0), move in STEPS (default 8)
//                                 equal steps to (X1, Y1), release (shift: tilt/turn)
//   wheel X Y CLICKS              move there and turn the wheel (CLICKS > 0 zooms in)
//   key NAME [shift] [ctrl]       press and release a key; NAME: A..Z, 0..9, Right, Left, Up,
//                                 Down, PageUp, PageDown, Home, End, Space, Enter, Escape, Tab,
//                                 Backspace, Plus, Minus, Comma, Period
//   type TEXT                     the rest of the line typed as characters (into a text box)
//   wait FRAMES                   draw FRAMES frames (1..100000)
//   flyto NAME                    fly to a radar, station, place or LAT,LON (the rest of the
//                                 line); the script goes on when the flight has landed
//   readout                       print the value under the pointer (`readout: ...` lines)
//   screenshot FILE.png           save the window, panel included
//
// Errors name the file and the line: "FILE line 7: drag: expected X0 Y0 X1 Y1 [STEPS] [shift]".
#include <atmoglobe/globe/Result.h>

#include <string>
#include <vector>

namespace atmoglobe::engine {

struct ScriptAction {
  enum class Kind { Camera, Move, Down, Up, Click, Drag, Wheel, Key, Type, Wait, FlyTo, Readout, Screenshot };
  Kind kind = Kind::Wait;
  int line = 0;                 ///< 1-based line in the file
  std::vector<double> numbers;  ///< the numeric arguments, in order
  std::string text;             ///< key name, typed text, place name or file
  int button = 0;               ///< 0 left, 1 right, 2 middle
  bool shift = false;
  bool ctrl = false;
};

/// The key names `key` accepts, in the order of the header comment.
const std::vector<std::string>& scriptKeyNames();

Result<std::vector<ScriptAction>> parseViewerScript(const std::string& text, const std::string& sourceName);
Result<std::vector<ScriptAction>> readViewerScript(const std::string& path);

}  // namespace atmoglobe::engine
