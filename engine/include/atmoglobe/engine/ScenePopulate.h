#pragma once
// Loading a scene description into a renderer: every volume layer, slice, model, overlay, the
// map context and the station markers, each input's failure reported where it was given. What
// `render`, `view` and the Python module's render do with a scene (tools/, python/).
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Result.h>

#include <string>
#include <vector>

namespace atmoglobe::engine {

/// Where a layer's key was given: "scene.json: /radars/2" + "/path", or the command-line option
/// when the origin is one ("--radar").
std::string sceneKeyAt(const std::string& origin, const char* key, const std::string& option);

/// Loads `scene` into `renderer` (empty); `markers` receives the scene's markers' stations.
/// An input that cannot be loaded (file not found, unreadable, bad content) is one message naming
/// where it was given and the file: "scene.json: /radars/2/path: file not found: /data/x.nc". With
/// `errors` null the first such message is returned (the caller stops); otherwise each is appended
/// to `errors`, that layer is left out of `scene` (so that `scene` describes what the renderer
/// holds, e.g. for SceneTime) and the others still load. scene.inputErrors (found when the scene
/// was resolved) are reported the same way. Load notes go to stderr (a progress bar on a terminal
/// when there are several inputs).
Status populateScene(SceneRendererGL& renderer, SceneDescription& scene, std::vector<Marker>* markers,
                     std::vector<std::string>* errors = nullptr);

}  // namespace atmoglobe::engine
