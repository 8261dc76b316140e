#include <atmoglobe/engine/ViewerPanelGL.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <epoxy/gl.h>
#include <imgui.h>

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
  ImGui::Text("frame %.1f ms", s.frameMilliseconds);
  if (!s.readout.empty()) {
    ImGui::Separator();
    ImGui::TextUnformatted("Under the cursor");
    for (const std::string& line : s.readout) ImGui::TextUnformatted(line.c_str());
  }
  if (ImGui::Button("Screenshot")) s.screenshotRequested = true;
  ImGui::End();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  return changed;
}

}  // namespace atmoglobe::engine
