#include <atmoglobe/engine/FlyToWindowGL.h>

#include <imgui.h>

namespace atmoglobe::engine {

void drawFlyToWindow(FlyToWindowState& state) {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 10.0f, io.DisplaySize.y - 10.0f), ImGuiCond_Always,
                          ImVec2(1.0f, 1.0f));
  ImGui::SetNextWindowBgAlpha(0.8f);
  ImGui::Begin("Fly to", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove);
  ImGui::SetNextItemWidth(180.0f);
  const bool enter = ImGui::InputTextWithHint("##flyto", "radar, station, place or lat,lon", state.query,
                                              sizeof state.query, ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::SameLine();
  const bool button = ImGui::Button("Fly");
  if ((enter || button) && state.query[0] != '\0') state.requested = true;
  if (!state.message.empty()) ImGui::TextUnformatted(state.message.c_str());
  ImGui::End();
}

}  // namespace atmoglobe::engine
