#pragma once
// Options shared by `render` and `view`: a scene file (or the embedded default scene)
// and command-line overrides of its camera, field of view, size and imagery.
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/globe/Result.h>

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace atmoglobe::tools {

struct SceneOptions {
  std::string sceneFile;
  std::string camera;  ///< "LAT,LON,HEIGHT,HEADING,PITCH,ROLL"
  double fovDeg = 0.0;  ///< 0: the scene's
  std::string size;     ///< "WxH"
  std::vector<std::string> imageryDirs;
  std::vector<std::string> xyzDirs;
  std::vector<std::string> markers;  ///< "LAT,LON[,HEIGHT[,LABEL]]"
};

void addSceneOptions(CLI::App& command, SceneOptions& options);

/// Directory of generated default data: $ATMOGLOBE_DATA_DIR, else the build's.
std::string dataDirectory();

/// The scene to render: the file (or the embedded default), then the overrides.
Result<engine::SceneDescription> resolveScene(const SceneOptions& options);

Result<engine::CameraPose> parseCameraPose(const std::string& text);
Status parseSize(const std::string& text, int* widthPx, int* heightPx);

}  // namespace atmoglobe::tools
