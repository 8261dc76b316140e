// Scene JSON (engine/Scene.h parseSceneJson: parsing and validation, no GL).
#include "FuzzCommon.h"

#include <atmoglobe/engine/Scene.h>

#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const std::string label = "fuzz-scene.json";
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  fuzz::checkError(engine::parseSceneJson(text, label, "/nonexistent-base", "/nonexistent-data"), label);
  return 0;
}
