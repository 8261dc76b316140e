#include <atmoglobe/engine/ViewerPanelGL.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <epoxy/gl.h>
#include <imgui.h>

#include <algorithm>
#include <filesystem>

namespace atmoglobe::engine {

namespace {
constexpr const char* kUiFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
bool gPanelAlive = false;
}  // namespace

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
  ImGui::Begin("atmoglobe", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
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
  ImGui::End();
  if (s.extraWindows) s.extraWindows();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  return changed;
}

}  // namespace atmoglobe::engine
