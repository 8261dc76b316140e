#include <atmoglobe/engine/FlyToWindowGL.h>

#include <imgui.h>

#include <utility>

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

namespace atmoglobe::engine {
void drawPointerMark() {
  const ImVec2 p = ImGui::GetIO().MousePos;
  if (p.x < -1e6f || p.y < -1e6f) return;  // ImGui's "no pointer"
  ImDrawList* draw = ImGui::GetForegroundDrawList();
  for (const auto& [color, width] :
       {std::pair{IM_COL32(0, 0, 0, 255), 3.0f}, std::pair{IM_COL32(255, 255, 255, 255), 1.0f}}) {
    draw->AddCircle(p, 7.0f, color, 16, width);
    draw->AddLine(ImVec2(p.x - 12.0f, p.y), ImVec2(p.x - 4.0f, p.y), color, width);
    draw->AddLine(ImVec2(p.x + 4.0f, p.y), ImVec2(p.x + 12.0f, p.y), color, width);
    draw->AddLine(ImVec2(p.x, p.y - 12.0f), ImVec2(p.x, p.y - 4.0f), color, width);
    draw->AddLine(ImVec2(p.x, p.y + 4.0f), ImVec2(p.x, p.y + 12.0f), color, width);
  }
}
}  // namespace atmoglobe::engine
