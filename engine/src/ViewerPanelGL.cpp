#include <atmoglobe/engine/ViewerPanelGL.h>

#include <atmoglobe/engine/GridSourceGL.h>
#include <atmoglobe/engine/LayerEdit.h>
#include <atmoglobe/engine/RadarNetworkSourceGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/volume/OpacityEditor.h>
#include <atmoglobe/volume/ValueHistogram.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <epoxy/gl.h>
#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>

namespace atmoglobe::engine {

namespace {
constexpr const char* kUiFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
bool gPanelAlive = false;
constexpr int kHistogramBins = 96;
constexpr float kEditorMaxWidth = 300.0f, kEditorHeight = 110.0f;
// Where the main panel's text wraps: 40 % of the window's width within these (pixels; the colour
// key is 260 wide).
constexpr float kPanelTextMinWidth = 280.0f, kPanelTextMaxWidth = 420.0f;
}  // namespace

struct ViewerPanelGL::Editing {
  /// Crop boxes being typed (applied with "Apply crop"), per layer in the single index.
  std::map<std::size_t, volume::CropBox> crops;
  std::map<std::size_t, double> probabilityThresholds;  ///< a grid's "prob:>=" value being edited
  std::map<std::size_t, bool> cropHeights;
  /// Histograms per layer, kept while the layer's GPU volume is the same object.
  struct Histogram {
    const void* volume = nullptr;
    volume::ValueHistogram h;
  };
  std::map<std::size_t, Histogram> histograms;
  /// The control point being dragged: layer and index.
  std::optional<std::pair<std::size_t, std::size_t>> dragging;
  float exaggeration = 1.0f;
  /// A map layer's description being edited, per surface index (applied when a field is left).
  std::map<std::size_t, SurfaceLayerDescription> surfaces;
  std::map<std::size_t, double> surfaceThresholds;  ///< a map's "prob:>=" value being edited
  std::string error;                                ///< the last edit's error, shown until the next edit succeeds
};

ViewerPanelGL::ViewerPanelGL() : editing_(std::make_unique<Editing>()) {}

Result<std::unique_ptr<ViewerPanelGL>> ViewerPanelGL::create(GLFWwindow* window) {
  if (gPanelAlive) return makeError("one viewer panel per process");
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini written into the user's working directory
  if (std::filesystem::exists(kUiFont)) io.Fonts->AddFontFromFileTTF(kUiFont, 15.0f);
  ImGui::StyleColorsDark();
  if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) {
    ImGui::DestroyContext();
    return makeError("Dear ImGui: the GLFW backend did not start");
  }
  if (!ImGui_ImplOpenGL3_Init("#version 410 core")) {
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    return makeError("Dear ImGui: the OpenGL 3 backend did not start");
  }
  gPanelAlive = true;
  return std::unique_ptr<ViewerPanelGL>(new ViewerPanelGL());
}

ViewerPanelGL::~ViewerPanelGL() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  gPanelAlive = false;
}

bool ViewerPanelGL::capturesMouse() { return gPanelAlive && ImGui::GetIO().WantCaptureMouse; }
bool ViewerPanelGL::capturesKeyboard() { return gPanelAlive && ImGui::GetIO().WantCaptureKeyboard; }

bool ViewerPanelGL::draw(ViewerPanelState& s) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);  // the window's: the scene's target may still be bound
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  bool changed = false;
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.8f);
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  // As tall as its contents, at most the window's height (then it scrolls).
  ImGui::SetNextWindowSizeConstraints(ImVec2(0.0f, 0.0f), ImVec2(FLT_MAX, std::max(100.0f, display.y - 20.0f)));
  ImGui::Begin("atmoglobe", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  // Long lines (a network's subtitle, a readout) wrap: the panel sizes itself to its contents, and
  // one unwrapped line made it as wide as the window, dimming the whole picture under its
  // background.
  ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + std::clamp(0.4f * display.x, kPanelTextMinWidth, kPanelTextMaxWidth));
  ImGui::PushItemWidth(kEditorMaxWidth - 120.0f);
  if (s.timePositions > 1) {
    ImGui::TextUnformatted(("Valid time  " + s.timeLabel).c_str());
    int position = s.timePosition;
    if (ImGui::SliderInt("##time", &position, 0, s.timePositions - 1, "")) {
      s.timePosition = position;
      changed = true;
    }
    if (ImGui::Button("<")) {
      s.timePosition = (s.timePosition + s.timePositions - 1) % s.timePositions;
      changed = true;
    }
    ImGui::SameLine();
    if (ImGui::Button(s.playing ? "Pause" : "Play")) {
      s.playing = !s.playing;
      changed = true;
    }
    ImGui::SameLine();
    if (ImGui::Button(">")) {
      s.timePosition = (s.timePosition + 1) % s.timePositions;
      changed = true;
    }
    ImGui::SameLine();
    ImGui::SetNextItemWidth(120.0f);  // the loop's speed: seconds per time position
    if (ImGui::SliderFloat("##speed", &s.playSeconds, 0.05f, 5.0f, "%.2f s/step", ImGuiSliderFlags_Logarithmic))
      changed = true;
    ImGui::Separator();
  }
  for (const std::string& line : s.layers) ImGui::TextUnformatted(line.c_str());
  for (const std::string& line : s.legend.subtitles) ImGui::TextUnformatted(line.c_str());
  if (s.legend.synthetic) ImGui::TextColored(ImVec4(1.0f, 0.25f, 0.25f, 1.0f), "SYNTHETIC DATA");
  // Colour keys, horizontal: the table's colours from low to high with a few values under them.
  for (const LegendKey& k : mergeLegendKeys(s.legend.keys)) {
    ImGui::TextUnformatted((k.title + "  [" + k.units + "]").c_str());
    const glm::dvec2 range = colorKeyRange(k.colors);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = 260.0f, height = 14.0f;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    for (int x = 0; x < static_cast<int>(width); ++x) {
      const double v = range.x + (x + 0.5) / width * (range.y - range.x);
      const volume::Rgba8 c = k.colors.map(static_cast<float>(v));
      draw->AddRectFilled(ImVec2(origin.x + static_cast<float>(x), origin.y),
                          ImVec2(origin.x + static_cast<float>(x) + 1.0f, origin.y + height),
                          IM_COL32(c.r, c.g, c.b, 255));
    }
    // Tick values under the bar, each at its place.
    const std::vector<double> ticks = niceTicks(range.x, range.y, 5);
    const int decimals = decimalsFor(ticks.size() > 1 ? ticks[1] - ticks[0] : 1.0);
    for (double t : ticks) {
      const std::string label = fixed(t, decimals);
      const float x = origin.x + static_cast<float>((t - range.x) / (range.y - range.x)) * width;
      draw->AddLine(ImVec2(x, origin.y + height), ImVec2(x, origin.y + height + 3.0f), IM_COL32(255, 255, 255, 255));
      const float w = ImGui::CalcTextSize(label.c_str()).x;
      draw->AddText(
          ImVec2(std::clamp(x - 0.5f * w, origin.x - 4.0f, origin.x + width + 4.0f - w), origin.y + height + 3.0f),
          IM_COL32(255, 255, 255, 255), label.c_str());
    }
    ImGui::Dummy(ImVec2(width, height + 4.0f + ImGui::GetTextLineHeight()));
  }
  ImGui::Text("frame %.1f ms", s.frameMilliseconds);
  if (!s.readout.empty()) {
    ImGui::Separator();
    ImGui::TextUnformatted("Under the cursor");
    for (const std::string& line : s.readout) ImGui::TextUnformatted(line.c_str());
  }
  if (ImGui::Button("Screenshot")) s.screenshotRequested = true;
  ImGui::SameLine();
  if (ImGui::Button("Save scene")) s.saveSceneRequested = true;
  ImGui::PopItemWidth();
  ImGui::PopTextWrapPos();
  const ImVec2 panelMin = ImGui::GetWindowPos();
  const ImVec2 panelMax(panelMin.x + ImGui::GetWindowSize().x, panelMin.y + ImGui::GetWindowSize().y);
  ImGui::End();
  // The layer controls in their own window at the top right, so the main panel (top left) keeps
  // its size and the middle of the picture stays free; at most the window's height less room
  // for a box at the bottom right (then it scrolls).
  if (s.scene) {
    ImGui::SetNextWindowPos(ImVec2(display.x - 10.0f, 10.0f), ImGuiCond_FirstUseEver, ImVec2(1.0f, 0.0f));
    ImGui::SetNextWindowBgAlpha(0.8f);
    ImGui::SetNextWindowSizeConstraints(ImVec2(0.0f, 0.0f), ImVec2(FLT_MAX, std::max(100.0f, display.y - 90.0f)));
    ImGui::Begin("Layers", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::PushItemWidth(kEditorMaxWidth - 120.0f);
    changed = drawLayers(*s.scene) || changed;
    ImGui::PopItemWidth();
    ImGui::End();
  }
  // The scale bar, bottom left over the picture: the one rendered PNGs carry (Legend.h).
  const float fbScale = std::max(ImGui::GetIO().DisplayFramebufferScale.x, 1.0f);
  if (const ScaleBar bar = scaleBarFor(s.legend.metersPerPixel, static_cast<int>(display.x * fbScale));
      s.scaleBar && bar.meters > 0.0) {
    ImDrawList* bg = ImGui::GetBackgroundDrawList();
    const float px = static_cast<float>(bar.lengthPx) / fbScale;
    const float yb = display.y - 14.0f;
    // Bottom left as on PNGs; right of the panel where the panel covers that corner.
    const bool covered = panelMin.x < 12.0f + px && panelMax.y > yb - 4.0f - ImGui::GetTextLineHeight();
    const float x0 = covered ? panelMax.x + 12.0f : 12.0f;
    bg->AddRectFilled(ImVec2(x0 - 1.0f, yb - 1.0f), ImVec2(x0 + px + 1.0f, yb + 3.0f), IM_COL32(0, 0, 0, 255));
    bg->AddRectFilled(ImVec2(x0, yb), ImVec2(x0 + px, yb + 2.0f), IM_COL32(255, 255, 255, 255));
    const std::string label = bar.label + " (at the centre)";
    const float th = ImGui::GetTextLineHeight();
    for (const ImVec2 d : {ImVec2(-1, 0), ImVec2(1, 0), ImVec2(0, -1), ImVec2(0, 1)})  // halo
      bg->AddText(ImVec2(x0 + d.x, yb - 4.0f - th + d.y), IM_COL32(0, 0, 0, 255), label.c_str());
    bg->AddText(ImVec2(x0, yb - 4.0f - th), IM_COL32(255, 255, 255, 255), label.c_str());
  }
  if (s.extraWindows) s.extraWindows();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  return changed;
}

namespace {
const char* const kModeLabels[] = {"DVR", "MIP", "iso"};  // allValues<VolumeRenderMode>'s order

template <std::size_t N>
bool comboOf(const char* label, std::string& value, const char* const (&choices)[N]) {
  bool changed = false;
  if (ImGui::BeginCombo(label, value.c_str())) {
    for (const char* c : choices) {
      if (ImGui::Selectable(c, value == c)) {
        changed = value != c;
        value = c;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

bool comboOf(const char* label, std::string& value, const std::vector<std::string>& choices) {
  bool changed = false;
  if (ImGui::BeginCombo(label, value.empty() ? "(default)" : value.c_str())) {
    for (const std::string& c : choices) {
      if (ImGui::Selectable(c.c_str(), value == c)) {
        changed = value != c;
        value = c;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

// An ensemble's members (docs/grids.md, "Ensembles"): one member, or a statistic over all of
// them (mean, spread, min, max, or the probability of >= a threshold typed in). Shown for grids
// read with members only; returns whether `statistic` changed.
bool hasMembers(const volume::GridVolume& g) {
  return !g.ensembleStatistic.empty() || g.member >= 0 ||
         std::any_of(g.extraDimensions.begin(), g.extraDimensions.end(),
                     [](const volume::GridExtraDimension& x) { return x.ensemble; });
}
bool ensembleControls(const volume::GridVolume& g, std::optional<volume::EnsembleStatistic>& statistic,
                      double& threshold) {
  if (!hasMembers(g)) return false;
  bool changed = false;
  const std::string current = statistic ? volume::toString(*statistic) : std::string("one member");
  if (ImGui::BeginCombo("members", current.c_str())) {
    for (const char* c : {"one member", "mean", "spread", "min", "max"}) {
      if (ImGui::Selectable(c, current == c) && current != c) {
        if (std::string(c) == "one member") statistic.reset();
        else statistic = *volume::parseEnsembleStatistic(c);
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  ImGui::InputDouble("threshold", &threshold, 0.0, 0.0, "%.6g");
  if (ImGui::Button("probability of >= threshold")) {
    volume::EnsembleStatistic p;
    p.kind = volume::EnsembleStatistic::Kind::Probability;
    p.comparison = ">=";
    p.threshold = threshold;
    statistic = p;
    changed = true;
  }
  return changed;
}

// A combo box over an enumerated setting, spelled as in scenes (VolumeLayer.h).
template <class E>
bool enumCombo(const char* label, E& value) {
  bool changed = false;
  if (ImGui::BeginCombo(label, nameOf(value))) {
    for (E c : allValues<E>()) {
      if (ImGui::Selectable(nameOf(c), value == c)) {
        changed = value != c;
        value = c;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}
}  // namespace

bool ViewerPanelGL::drawLayers(SceneRendererGL& scene) {
  Editing& e = *editing_;
  bool changed = false;
  auto report = [&](const Status& st) {
    if (!st) {
      e.error = st.error();
    } else {
      e.error.clear();
    }
    changed = true;
  };
  std::vector<std::size_t> order = scene.volumeOrder();
  for (std::size_t position = 0; position < order.size(); ++position) {
    const std::size_t i = order[position];
    VolumeSourceGL& layer = scene.layer(i);
    ImGui::PushID(static_cast<int>(i));
    if (ImGui::Checkbox("##on", &layer.visible)) changed = true;
    ImGui::SameLine();
    if (ImGui::ArrowButton("##up", ImGuiDir_Up) && position > 0) {
      report(scene.setVolumeOrder(moveInOrder(order, position, -1)));
    }
    ImGui::SameLine();
    if (ImGui::ArrowButton("##down", ImGuiDir_Down) && position + 1 < order.size()) {
      report(scene.setVolumeOrder(moveInOrder(order, position, +1)));
    }
    ImGui::SameLine();
    const std::string title = layer.title();
    // Closed until opened (ATMOGLOBE_PANEL_OPEN=1 opens the first, for screenshots of the
    // controls): the window stays small and leaves the picture free.
    static const bool openFirst = std::getenv("ATMOGLOBE_PANEL_OPEN") != nullptr;
    const bool open = ImGui::TreeNodeEx("##layer", openFirst && position == 0 ? ImGuiTreeNodeFlags_DefaultOpen : 0,
                                        "%s", title.c_str());
    if (!open) {
      ImGui::PopID();
      continue;
    }
    VolumeLayerDescription d = scene.volumeDescription(i);
    bool edited = false;
    // Field or variable (files holding several): read again from the file, at the step shown.
    if (const std::vector<std::string> fields = layer.fieldChoices(); fields.size() > 1) {
      std::string field = layer.fieldShown();
      if (comboOf(d.kind == VolumeKind::Radar ? "field" : "variable", field, fields)) {
        d.field = field;
        d.settings.opacityPoints.clear();  // in the old field's units
        d.settings.valueRange.reset();
        d.settings.opacity.clear();
        d.isoValue.reset();  // the middle of its range
        edited = true;
      }
    }
    edited = comboOf("colours", d.colors, colorTableChoices()) || edited;
    // Mode and iso value.
    const auto& modes = allValues<volume::VolumeRenderMode>();
    for (std::size_t m = 0; m < modes.size(); ++m) {
      if (m > 0) ImGui::SameLine();
      if (ImGui::RadioButton(kModeLabels[m], d.mode == modes[m]) && d.mode != modes[m]) {
        d.mode = modes[m];
        edited = true;
      }
    }
    const VolumeRenderOptions& options = layer.options();
    const volume::ValueRange range = layer.colourRange();
    if (d.mode == volume::VolumeRenderMode::Iso) {
      float iso = static_cast<float>(options.render.isoValue);
      // Applied while dragging (options only, cheap): a value kept only until release would be
      // lost, since the slider's variable is refilled from the layer every frame.
      if (ImGui::SliderFloat("iso value", &iso, static_cast<float>(range.minValue), static_cast<float>(range.maxValue),
                             "%.1f")) {
        d.isoValue = iso;
        edited = true;
      }
    }
    // Transfer-function editor: opacity control points over the histogram of the field's values.
    if (ImGui::TreeNodeEx("transfer function", ImGuiTreeNodeFlags_DefaultOpen)) {
      const void* volumeId = &layer.volume();
      Editing::Histogram& cached = e.histograms[i];
      if (cached.volume != volumeId) {
        cached.volume = volumeId;
        cached.h = layer.histogram(kHistogramBins);
      }
      const volume::ValueHistogram& h = cached.h;
      const volume::TransferFunction& tf = options.render.transfer;
      std::vector<glm::dvec2> points = volume::opacityCurveOf(tf);
      double lo = h.lo, hi = h.hi;
      for (const glm::dvec2& p : points) {
        if (std::isfinite(p.x) && std::abs(p.x) < 1e29) {
          lo = std::min(lo, p.x);
          hi = std::max(hi, p.x);
        }
      }
      const ImVec2 o = ImGui::GetCursorScreenPos();
      const float editorWidth = kEditorMaxWidth;  // the window fits itself to it
      ImGui::InvisibleButton("##tf", ImVec2(editorWidth, kEditorHeight),
                             ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
      const bool hovered = ImGui::IsItemHovered();
      ImDrawList* draw = ImGui::GetWindowDrawList();
      draw->AddRectFilled(o, ImVec2(o.x + editorWidth, o.y + kEditorHeight), IM_COL32(20, 20, 24, 255));
      auto xOf = [&](double v) { return o.x + static_cast<float>((v - lo) / (hi - lo)) * editorWidth; };
      auto yOf = [&](double a) { return o.y + static_cast<float>(1.0 - a) * kEditorHeight; };
      // Histogram (counts on a log scale, so rare strong echoes still show), coloured by the table.
      const double logMax = std::log1p(static_cast<double>(h.largestCount()));
      const double binWidth = (h.hi - h.lo) / static_cast<double>(h.counts.size());
      for (std::size_t b = 0; b < h.counts.size() && logMax > 0.0; ++b) {
        const double v0 = h.lo + static_cast<double>(b) * binWidth;
        const double frac = std::log1p(static_cast<double>(h.counts[b])) / logMax;
        const volume::Rgba8 c = tf.colors.map(static_cast<float>(v0 + 0.5 * binWidth));
        draw->AddRectFilled(ImVec2(xOf(v0), yOf(frac)), ImVec2(std::max(xOf(v0 + binWidth), xOf(v0) + 1.0f), yOf(0.0)),
                            IM_COL32(c.r / 2 + 40, c.g / 2 + 40, c.b / 2 + 40, 255));
      }
      // The opacity curve and its points.
      std::vector<ImVec2> line;
      line.emplace_back(o.x, yOf(points.front().y));  // the end points' opacity beyond them (the ramp: 0 below)
      for (const glm::dvec2& p : points) line.emplace_back(xOf(p.x), yOf(p.y));
      line.emplace_back(o.x + editorWidth, yOf(points.back().y));
      draw->AddPolyline(line.data(), static_cast<int>(line.size()), IM_COL32(255, 255, 255, 255), 0, 2.0f);
      for (const glm::dvec2& p : points)
        draw->AddCircleFilled(ImVec2(xOf(p.x), yOf(p.y)), 4.0f, IM_COL32(255, 200, 40, 255));
      // Editing: left click adds a point (or takes the one under the pointer to drag), right click
      // deletes the point under the pointer.
      const ImVec2 mouse = ImGui::GetIO().MousePos;
      const glm::dvec2 at(lo + (mouse.x - o.x) / editorWidth * (hi - lo), 1.0 - (mouse.y - o.y) / kEditorHeight);
      const glm::dvec2 perPixel((hi - lo) / editorWidth, 1.0 / kEditorHeight);
      bool pointsEdited = false;
      if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        if (auto picked = volume::pickOpacityPoint(points, at, perPixel, 6.0)) {
          e.dragging = std::make_pair(i, *picked);
        } else {
          e.dragging = std::make_pair(i, volume::addOpacityPoint(points, at));
          pointsEdited = true;
        }
      }
      if (e.dragging && e.dragging->first == i && ImGui::IsMouseDown(ImGuiMouseButton_Left) &&
          ImGui::IsMouseDragging(ImGuiMouseButton_Left, 0.0f)) {
        pointsEdited = volume::moveOpacityPoint(points, e.dragging->second, at, perPixel.x) || pointsEdited;
      }
      if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) e.dragging.reset();
      if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Right)) {
        if (auto picked = volume::pickOpacityPoint(points, at, perPixel, 6.0))
          pointsEdited = volume::deleteOpacityPoint(points, *picked) || pointsEdited;
      }
      if (pointsEdited) {
        d.settings.opacityPoints = points;
        edited = true;
      }
      ImGui::Text("%.1f .. %.1f   %zu points%s", lo, hi, points.size(),
                  tf.opacityPoints.empty() ? " (default ramp)" : "");
      ImGui::TextDisabled("click: add/drag  right click: delete");
      if (ImGui::Button("Reset opacity")) {
        d.settings.opacityPoints.clear();
        d.settings.opacity.clear();
        edited = true;
      }
      ImGui::TreePop();
    }
    if (ImGui::TreeNode("quality")) {
      float step = static_cast<float>(d.stepMeters);
      if (ImGui::SliderFloat("step (m)", &step, 25.0f, 2000.0f, "%.0f", ImGuiSliderFlags_Logarithmic)) {
        d.stepMeters = step;
        edited = true;
      }
      {
        // The step rule (docs/volume-rendering.md): 0 = the fixed step above everywhere.
        float perCell = static_cast<float>(samplesPerCellOf(d));
        if (ImGui::SliderFloat("samples per cell", &perCell, 0.0f, 8.0f, "%.1f")) {
          d.samplesPerCell = perCell;
          edited = true;
        }
      }
      float scale = static_cast<float>(d.imageScale);
      if (ImGui::SliderFloat("image scale", &scale, 0.1f, 1.0f, "%.2f")) {
        d.imageScale = scale;
        edited = true;
      }
      if (d.imageScale < 1.0) {
        // Adaptive refinement (docs/volume-rendering.md): -1 = off, the small image upsampled.
        float threshold = static_cast<float>(d.refineThreshold);
        if (ImGui::SliderFloat("refine threshold", &threshold, -1.0f, 16.0f, "%.0f /255")) {
          d.refineThreshold = threshold < 0.0f ? -1.0 : std::round(threshold);
          edited = true;
        }
      }
      edited = enumCombo("interpolation", d.interpolation) || edited;
      if (d.kind == VolumeKind::Radar) edited = enumCombo("beam", d.beam) || edited;  // the beam model is a radar's
      if (const auto* network = dynamic_cast<const RadarNetworkSourceGL*>(&layer)) {
        // A network's overlap rule (docs/networks.md): one value where radars overlap, or each
        // radar apart (integrate; the only rule for velocity, whose sites cannot be combined).
        const volume::OverlapRule rule = d.overlap.value_or(network->rule());
        const bool combinable = network->valuesCombine();
        std::vector<volume::OverlapRule> choices{volume::OverlapRule::Integrate};
        if (combinable)
          choices.insert(choices.begin(), {volume::OverlapRule::WeightedMean, volume::OverlapRule::LowestBeam,
                                           volume::OverlapRule::Maximum});
        if (!combinable) ImGui::TextDisabled("values of different sites are not combined: each radar apart");
        if (ImGui::BeginCombo("overlap", volume::toString(rule))) {
          for (volume::OverlapRule c : choices) {
            if (ImGui::Selectable(volume::toString(c), rule == c) && c != rule) {
              d.overlap = c;
              edited = true;
            }
          }
          ImGui::EndCombo();
        }
        // Seen from far away: slabs integrated once instead of a march per pixel (FarFieldGL.h).
        FarField farField = d.farField.value_or(FarField::Off);
        if (enumCombo("far field", farField)) {
          d.farField = farField;
          edited = true;
        }
      }
      if (const auto* grid = dynamic_cast<const GridSourceGL*>(&layer)) {
        const volume::GridVolume& g = grid->gridVolume().grid();
        if (!e.probabilityThresholds.count(i)) e.probabilityThresholds[i] = 0.5 * (g.valueMin + g.valueMax);
        edited = ensembleControls(g, d.ensemble, e.probabilityThresholds[i]) || edited;
      }
      edited = enumCombo("classification", d.classification) || edited;
      ImGui::TreePop();
    }
    if (ImGui::TreeNode("crop box")) {
      if (!e.crops.count(i)) {
        e.crops[i] = d.settings.crop;
        e.cropHeights[i] = !d.settings.crop.coversEveryHeight();
      }
      volume::CropBox& c = e.crops[i];
      ImGui::InputDouble("south (deg)", &c.southDeg, 0.1, 1.0, "%.3f");
      ImGui::InputDouble("north (deg)", &c.northDeg, 0.1, 1.0, "%.3f");
      ImGui::InputDouble("west (deg)", &c.westDeg, 0.1, 1.0, "%.3f");
      ImGui::InputDouble("east (deg)", &c.eastDeg, 0.1, 1.0, "%.3f");
      bool& heights = e.cropHeights[i];
      ImGui::Checkbox("heights (m above sea level)", &heights);
      if (heights) {
        if (std::isinf(c.bottomMeters)) c.bottomMeters = 0.0;
        if (std::isinf(c.topMeters)) c.topMeters = 20000.0;
        ImGui::InputDouble("bottom (m)", &c.bottomMeters, 100.0, 1000.0, "%.0f");
        ImGui::InputDouble("top (m)", &c.topMeters, 100.0, 1000.0, "%.0f");
      }
      if (ImGui::Button("Apply crop")) {
        volume::CropBox box = c;
        if (!heights) box.bottomMeters = -INFINITY, box.topMeters = INFINITY;
        d.settings.crop = box;
        edited = true;
      }
      ImGui::SameLine();
      if (ImGui::Button("No crop")) {
        c = volume::CropBox{};
        heights = false;
        d.settings.crop = c;
        edited = true;
      }
      ImGui::TreePop();
    }
    if (edited) {
      report(scene.setVolumeDescription(i, d));
    }
    ImGui::TreePop();
    ImGui::PopID();
  }
  changed = drawSurfaces(scene) || changed;
  // Scene-wide: vertical exaggeration (volumes re-uploaded or read again when released).
  if (e.exaggeration != static_cast<float>(scene.verticalExaggeration()) && !ImGui::IsAnyItemActive())
    e.exaggeration = static_cast<float>(scene.verticalExaggeration());
  ImGui::SliderFloat("vertical exaggeration", &e.exaggeration, 1.0f, 20.0f, "x%.1f", ImGuiSliderFlags_Logarithmic);
  if (ImGui::IsItemDeactivatedAfterEdit()) report(scene.changeVerticalExaggeration(e.exaggeration));
  if (!e.error.empty()) {
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + kEditorMaxWidth);
    ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", e.error.c_str());
    ImGui::PopTextWrapPos();
  }
  // What is loaded: CPU and GPU bytes per volume layer.
  if (ImGui::CollapsingHeader("Loaded (memory)", ImGuiTreeNodeFlags_DefaultOpen) &&
      ImGui::BeginTable("##memory", 3, ImGuiTableFlags_SizingFixedFit)) {
    ImGui::TableSetupColumn("layer");
    ImGui::TableSetupColumn("CPU");
    ImGui::TableSetupColumn("GPU");
    ImGui::TableHeadersRow();
    std::uint64_t cpu = 0, gpu = 0;
    for (const LayerMemory& m : scene.layerMemory()) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(m.name.c_str());
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(formatBytes(m.cpuBytes).c_str());
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(formatBytes(m.gpuBytes).c_str());
      cpu += m.cpuBytes;
      gpu += m.gpuBytes;
    }
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted("total");
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(formatBytes(cpu).c_str());
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(formatBytes(gpu).c_str());
    ImGui::EndTable();
  }
  return changed;
}

bool ViewerPanelGL::drawSurfaces(SceneRendererGL& scene) {
  Editing& e = *editing_;
  bool changed = false;
  const auto& surfaces = scene.surfaces();
  if (!surfaces.empty()) {
    ImGui::Separator();
    ImGui::TextUnformatted("Maps");
  }
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const SurfaceFieldGL& layer = *surfaces[i];
    ImGui::PushID(static_cast<int>(1000000 + i));
    bool visible = layer.visible;
    if (ImGui::Checkbox("##on", &visible)) {
      scene.setSurfaceVisible(i, visible);
      changed = true;
    }
    ImGui::SameLine();
    static const bool openFirst = std::getenv("ATMOGLOBE_PANEL_OPEN") != nullptr;  // as the volume layers
    if (!ImGui::TreeNodeEx("##map", openFirst && i == 0 ? ImGuiTreeNodeFlags_DefaultOpen : 0, "%s",
                           layer.field().name.c_str())) {
      ImGui::PopID();
      continue;
    }
    // The pending description follows the layer's except while a field is being typed in.
    if (!e.surfaces.count(i) || !ImGui::IsAnyItemActive()) e.surfaces[i] = layer.description();
    SurfaceLayerDescription& d = e.surfaces[i];
    bool apply = false;
    if (d.pressureHpa) {
      ImGui::InputDouble("pressure (hPa)", &*d.pressureHpa, 50.0, 100.0, "%.0f");
      apply = ImGui::IsItemDeactivatedAfterEdit() || apply;
    } else if (d.level) {
      ImGui::InputInt("level (0 = lowest)", &*d.level);
      apply = ImGui::IsItemDeactivatedAfterEdit() || apply;
    }
    apply = comboOf("colours", d.colors, colorTableChoices()) || apply;
    float opacity = static_cast<float>(d.fill ? d.opacity : 0.0);
    if (ImGui::SliderFloat("fill opacity", &opacity, 0.0f, 1.0f, "%.2f")) {
      d.opacity = opacity;
      d.fill = opacity > 0.0f;
    }
    apply = ImGui::IsItemDeactivatedAfterEdit() || apply;
    if (d.contourValues.empty()) {
      double interval = d.contourInterval.value_or(0.0);
      if (ImGui::InputDouble("contour interval (0: none)", &interval, 0.0, 0.0, "%.6g")) {
        if (interval > 0.0) {
          d.contourInterval = interval;
        } else {
          d.contourInterval.reset();
        }
      }
      apply = ImGui::IsItemDeactivatedAfterEdit() || apply;
    }
    bool wind = !d.wind.empty();
    if (ImGui::Checkbox("wind barbs", &wind)) {
      d.wind = wind ? std::string("auto") : std::string();
      apply = true;
    }
    // An ensemble: one member (by number) or a statistic over all of them.
    const volume::GridVolume& g = layer.field().grid;
    std::optional<volume::EnsembleStatistic> statistic;
    if (auto parsed = volume::parseEnsembleStatistic(d.ensemble); !d.ensemble.empty() && parsed) statistic = *parsed;
    if (!e.surfaceThresholds.count(i)) e.surfaceThresholds[i] = 0.5 * (g.valueMin + g.valueMax);
    if (ensembleControls(g, statistic, e.surfaceThresholds[i])) {
      d.ensemble = statistic ? volume::toString(*statistic) : std::string();
      if (statistic) d.member = -1;
      apply = true;
    }
    if (hasMembers(g) && d.ensemble.empty()) {
      ImGui::InputInt("member", &d.member);
      apply = ImGui::IsItemDeactivatedAfterEdit() || apply;
    }
    if (apply) {
      const Status st = scene.setSurfaceDescription(i, d);
      e.error = st ? std::string() : st.error();
      e.surfaces.erase(i);
      changed = true;
    }
    ImGui::TreePop();
    ImGui::PopID();
  }
  return changed;
}

}  // namespace atmoglobe::engine
