#include <atmoglobe/engine/ViewerScript.h>

#include <atmoglobe/globe/Text.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace atmoglobe::engine {

namespace {

std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string w;
  while (ss >> w) out.push_back(w);
  return out;
}

bool number(const std::string& w, double* x) {
  std::size_t used = 0;
  try {
    *x = std::stod(w, &used);
  } catch (...) {
    return false;
  }
  return used == w.size() && std::isfinite(*x);
}

/// The text after the first word, blanks trimmed.
std::string rest(const std::string& line) {
  const std::string_view text = trimAscii(line);
  const auto gap = text.find_first_of(" \t");
  if (gap == std::string_view::npos) return "";
  return std::string(trimAscii(text.substr(gap)));
}

}  // namespace

const std::vector<std::string>& scriptKeyNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (char c = 'A'; c <= 'Z'; ++c) n.emplace_back(1, c);
    for (char c = '0'; c <= '9'; ++c) n.emplace_back(1, c);
    for (const char* k : {"Right", "Left", "Up", "Down", "PageUp", "PageDown", "Home", "End", "Space", "Enter",
                          "Escape", "Tab", "Backspace", "Plus", "Minus", "Comma", "Period"})
      n.emplace_back(k);
    return n;
  }();
  return names;
}

Result<std::vector<ScriptAction>> parseViewerScript(const std::string& text, const std::string& sourceName) {
  using Kind = ScriptAction::Kind;
  struct Syntax {
    const char* name;
    Kind kind;
    std::size_t minNumbers, maxNumbers;
    const char* usage;
  };
  static const Syntax syntax[] = {
      {"camera", Kind::Camera, 3, 6, "camera LAT LON HEIGHT [HEADING PITCH [ROLL]]"},
      {"move", Kind::Move, 2, 2, "move X Y"},
      {"down", Kind::Down, 0, 0, "down [left|right|middle] [shift] [ctrl]"},
      {"up", Kind::Up, 0, 0, "up [left|right|middle]"},
      {"click", Kind::Click, 2, 2, "click X Y [left|right|middle]"},
      {"drag", Kind::Drag, 4, 5, "drag X0 Y0 X1 Y1 [STEPS] [shift] [ctrl]"},
      {"wheel", Kind::Wheel, 3, 3, "wheel X Y CLICKS"},
      {"key", Kind::Key, 0, 0, "key NAME [shift] [ctrl]"},
      {"type", Kind::Type, 0, 0, "type TEXT"},
      {"wait", Kind::Wait, 1, 1, "wait FRAMES"},
      {"flyto", Kind::FlyTo, 0, 0, "flyto NAME"},
      {"readout", Kind::Readout, 0, 0, "readout"},
      {"screenshot", Kind::Screenshot, 0, 0, "screenshot FILE.png"},
  };
  std::vector<ScriptAction> actions;
  std::stringstream in(text);
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> w = words(line);
    if (w.empty() || w[0][0] == '#') continue;
    const std::string where = sourceName + " line " + std::to_string(lineNumber) + ": ";
    const auto s = std::find_if(std::begin(syntax), std::end(syntax), [&](const Syntax& x) { return w[0] == x.name; });
    if (s == std::end(syntax)) {
      return makeError(where + "unknown action '" + w[0] +
                       "' (camera, move, down, up, click, drag, wheel, key, type, wait, flyto, readout, screenshot)");
    }
    const std::string usage = where + s->name + ": expected " + s->usage;
    ScriptAction a;
    a.kind = s->kind;
    a.line = lineNumber;
    if (a.kind == Kind::Type || a.kind == Kind::FlyTo || a.kind == Kind::Screenshot) {
      a.text = rest(line);
      if (a.text.empty()) return makeError(usage);
      if (a.kind == Kind::Screenshot && (a.text.size() < 5 || a.text.substr(a.text.size() - 4) != ".png"))
        return makeError(where + "screenshot: the file must end in .png, not '" + a.text + "'");
      actions.push_back(std::move(a));
      continue;
    }
    std::size_t i = 1;
    if (a.kind == Kind::Key) {
      if (w.size() < 2) return makeError(usage);
      const auto& names = scriptKeyNames();
      const auto k = std::find_if(names.begin(), names.end(),
                                  [&](const std::string& n) { return equalsIgnoringCaseAscii(n, w[1]); });
      if (k == names.end()) return makeError(where + "key: unknown key '" + w[1] + "'");
      a.text = *k;
      i = 2;
    }
    for (; i < w.size(); ++i) {
      double x = 0.0;
      if (!number(w[i], &x)) break;
      a.numbers.push_back(x);
    }
    if (a.numbers.size() < s->minNumbers || a.numbers.size() > s->maxNumbers) return makeError(usage);
    for (; i < w.size(); ++i) {
      const std::string& word = w[i];
      const bool buttonWord = word == "left" || word == "right" || word == "middle";
      if (buttonWord && (a.kind == Kind::Down || a.kind == Kind::Up || a.kind == Kind::Click)) {
        a.button = word == "left" ? 0 : word == "right" ? 1 : 2;
      } else if (word == "shift" && (a.kind == Kind::Down || a.kind == Kind::Drag || a.kind == Kind::Key)) {
        a.shift = true;
      } else if (word == "ctrl" && (a.kind == Kind::Down || a.kind == Kind::Drag || a.kind == Kind::Key)) {
        a.ctrl = true;
      } else {
        return makeError(usage + " (unexpected '" + word + "')");
      }
    }
    if (a.kind == Kind::Wait &&
        !(a.numbers[0] >= 1 && a.numbers[0] <= 100000 && a.numbers[0] == std::floor(a.numbers[0])))
      return makeError(where + "wait: FRAMES must be a whole number in 1..100000");
    if (a.kind == Kind::Drag && a.numbers.size() == 5 &&
        !(a.numbers[4] >= 1 && a.numbers[4] <= 1000 && a.numbers[4] == std::floor(a.numbers[4])))
      return makeError(where + "drag: STEPS must be a whole number in 1..1000");
    if (a.kind == Kind::Wheel && std::abs(a.numbers[2]) > 100) return makeError(where + "wheel: at most 100 clicks");
    if (a.kind == Kind::Camera) {
      const auto& n = a.numbers;
      if (std::abs(n[0]) > 90.0 || std::abs(n[1]) > 360.0 || !(n[2] >= 1.0 && n[2] <= 1e8) ||
          (n.size() > 4 && std::abs(n[4]) > 90.0))
        return makeError(where +
                         "camera: latitude in [-90, 90], longitude in [-360, 360], height in [1, 1e8] m, "
                         "pitch in [-90, 90]");
    }
    actions.push_back(std::move(a));
  }
  return actions;
}

Result<std::vector<ScriptAction>> readViewerScript(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open the script");
  std::stringstream text;
  text << in.rdbuf();
  if (text.str().size() > (1u << 24)) return makeError(path + ": a script over 16 MiB");
  return parseViewerScript(text.str(), path);
}

}  // namespace atmoglobe::engine
