// Loading a scene description into a renderer (ScenePopulate.h).
#include <atmoglobe/engine/ScenePopulate.h>

#include <atmoglobe/globe/Progress.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/StationList.h>

#include <filesystem>
#include <iostream>
#include <optional>
#include <type_traits>
#include <utility>

namespace atmoglobe::engine {

namespace {
const auto& keyAt = sceneKeyAt;
}  // namespace

std::string sceneKeyAt(const std::string& origin, const char* key, const std::string& option) {
  return origin.rfind("--", 0) == 0 ? option : origin + "/" + key;
}

Status populateScene(engine::SceneRendererGL& renderer, engine::SceneDescription& scene,
                     std::vector<engine::Marker>* markers, std::vector<std::string>* errors) {
  if (auto st = renderer.setVerticalExaggeration(scene.verticalExaggeration); !st) return st;
  if (scene.memoryBudgetMb > 0.0)
    renderer.setMemoryBudget(static_cast<std::uint64_t>(scene.memoryBudgetMb * 1048576.0));
  // One input's failure: fatal without `errors`, else kept and the layer left out.
  auto problem = [&](const std::string& message) -> Status {
    if (!errors) return makeError(message);
    errors->push_back(message);
    return Ok{};
  };
  for (const std::string& e : scene.inputErrors)
    if (auto st = problem(e); !st) return st;
  const auto& origins = scene.origins;
  const std::size_t inputs = scene.volumes.size() + scene.slices.size() + scene.overlays.size() + scene.surfaces.size();
  // Several inputs: progress (a bar on a terminal, lines in logs); one is quick enough alone.
  std::optional<globe::Progress> progress;
  if (inputs > 1) progress.emplace("loading", inputs);
  auto step = [&](const std::string& path) {
    if (progress) progress->advance(1, std::filesystem::path(path).filename().string());
  };
  auto say = [&](const std::string& line) {
    if (progress) progress->print(line);
    else std::cerr << line << "\n";
  };
  engine::SceneDescription::Origins kept;
  {
    std::vector<engine::VolumeLayerDescription> loaded;
    for (std::size_t i = 0; i < scene.volumes.size(); ++i) {
      const engine::VolumeLayerDescription& d = scene.volumes[i];
      const bool radar = d.kind == engine::VolumeKind::Radar;
      const std::string origin = engine::layerOrigin(origins.volumes, i, radar ? "--radar" : "--grid");
      Status st = engine::checkInputFile(d.path, keyAt(origin, "path", origin));
      if (st && d.colors.size() > 4 && d.colors.substr(d.colors.size() - 4) == ".pal")
        st = engine::checkInputFile(d.colors, keyAt(origin, "colors", radar ? "--colors" : "--grid-colors"));
      std::string line;
      if (st) {
        auto layer = renderer.addVolume(d);
        if (layer) line = (*layer)->loadNote();
        else st = makeError(origin + ": " + layer.error());
      }
      step(d.path);
      if (!st) {
        if (auto f = problem(st.error()); !f) return f;
        continue;
      }
      say(line);
      loaded.push_back(d);
      kept.volumes.push_back(origin);
    }
    scene.volumes = std::move(loaded);
  }
  // Slices and maps: each input checked, added, reported in a line; a failure is one problem.
  // `input(d)`: its file and the key naming it; `add(d)`: the renderer's line for the user.
  auto loadEach = [&](auto& layers, const std::vector<std::string>& layerOrigins, const char* fallback,
                      std::vector<std::string>& keptOrigins, auto input, auto add) -> Status {
    std::remove_reference_t<decltype(layers)> loaded;
    for (std::size_t i = 0; i < layers.size(); ++i) {
      const auto& d = layers[i];
      const std::string origin = engine::layerOrigin(layerOrigins, i, fallback);
      const auto [path, key] = input(d);
      Status st = engine::checkInputFile(path, keyAt(origin, key, origin));
      std::string line;
      if (st) {
        Result<std::string> added = add(d);
        if (added) line = *added;
        else st = makeError(origin + ": " + added.error());
      }
      step(path);
      if (!st) {
        if (auto f = problem(st.error()); !f) return f;
        continue;
      }
      say(line);
      loaded.push_back(d);
      keptOrigins.push_back(origin);
    }
    layers = std::move(loaded);
    return Ok{};
  };
  if (Status st = loadEach(
          scene.slices, origins.slices, "--slice-height-m/--slice-path", kept.slices,
          [](const engine::SliceLayerDescription& d) {
            const bool radar = d.source.kind == volume::SliceSourceOptions::Kind::Radar;
            return std::pair{d.source.path, radar ? "radar" : "grid"};
          },
          [&](const engine::SliceLayerDescription& d) -> Result<std::string> {
            auto added = renderer.addSlice(d);
            if (!added) return added;
            return d.source.path + ": slice " + *added;
          });
      !st)
    return st;
  if (Status st = loadEach(
          scene.surfaces, origins.surfaces, "--surface", kept.surfaces,
          [](const engine::SurfaceLayerDescription& d) {
            return std::pair{d.path, "path"};
          },
          [&](const engine::SurfaceLayerDescription& d) { return renderer.addSurface(d); });
      !st)
    return st;
  for (const std::string& m : scene.models) {
    if (auto st = renderer.addModel(m); !st)
      if (auto f = problem("--cones: " + st.error()); !f) return f;
  }
  // Map context on by default; missing GSHHG files only warn (the picture still renders).
  if (auto st = renderer.setMapContext(scene.mapContext); !st)
    std::cerr << "warning: " << st.error() << " (drawn without coastlines and borders; --no-map silences this)\n";
  if (Status st = loadEach(
          scene.overlays, origins.overlays, "--overlay", kept.overlays,
          [](const engine::MapOverlayDescription& d) {
            return std::pair{d.path, "path"};
          },
          [&](const engine::MapOverlayDescription& d) -> Result<std::string> {
            auto added = renderer.addOverlay(d);
            if (!added) return added;
            return d.path + ": overlay: " + *added;
          });
      !st)
    return st;
  if (progress) progress->finish();
  renderer.setRangeRings(scene.rangeRings);
  if (!scene.stationsPath.empty()) {
    const std::string origin = scene.origins.stations.empty() ? "--stations" : scene.origins.stations;
    Status st = engine::checkInputFile(scene.stationsPath, origin);
    if (st) {
      auto stations = volume::readStationList(scene.stationsPath);
      if (!stations) {
        st = makeError(origin + ": " + stations.error());
      } else {
        const auto& geoid = volume::defaultEgm96Grid();
        for (const volume::Station& s : *stations) {
          engine::Marker m;
          m.latDeg = s.latDeg;
          m.lonDeg = s.lonDeg;
          // Station elevations are above mean sea level; markers sit on the ellipsoid's scale.
          m.heightMeters = s.elevationMeters + (geoid ? geoid->undulationMeters(s.latDeg, s.lonDeg) : 0.0);
          m.color = glm::vec3(1.0f, 0.85f, 0.1f);
          m.sizePx = 9.0f;
          m.label = s.id;
          markers->push_back(m);
        }
      }
    }
    if (!st)
      if (auto f = problem(st.error()); !f) return f;
  }
  kept.imagery = scene.origins.imagery;
  kept.stations = scene.origins.stations;
  scene.origins = std::move(kept);
  return Ok{};
}

}  // namespace atmoglobe::engine
