// Loading a scene description into a renderer (ScenePopulate.h).
#include <atmoglobe/engine/ScenePopulate.h>

#include <atmoglobe/globe/Progress.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/StationList.h>

#include <filesystem>
#include <iostream>
#include <optional>

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
  {
    std::vector<engine::SliceLayerDescription> loaded;
    for (std::size_t i = 0; i < scene.slices.size(); ++i) {
      const engine::SliceLayerDescription& d = scene.slices[i];
      const bool isRadar = d.source.kind == volume::SliceSourceOptions::Kind::Radar;
      const std::string origin = engine::layerOrigin(origins.slices, i, "--slice-height-m/--slice-path");
      Status st = engine::checkInputFile(d.source.path, keyAt(origin, isRadar ? "radar" : "grid", origin));
      std::string line;
      if (st) {
        auto added = renderer.addSlice(d);
        if (added) line = *added;
        else st = makeError(origin + ": " + added.error());
      }
      step(d.source.path);
      if (!st) {
        if (auto f = problem(st.error()); !f) return f;
        continue;
      }
      say(d.source.path + ": slice " + line);
      loaded.push_back(d);
      kept.slices.push_back(origin);
    }
    scene.slices = std::move(loaded);
  }
  {
    std::vector<engine::SurfaceLayerDescription> loaded;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const engine::SurfaceLayerDescription& d = scene.surfaces[i];
      const std::string origin = engine::layerOrigin(origins.surfaces, i, "--surface");
      Status st = engine::checkInputFile(d.path, keyAt(origin, "path", origin));
      std::string line;
      if (st) {
        auto added = renderer.addSurface(d);
        if (added) line = *added;
        else st = makeError(origin + ": " + added.error());
      }
      step(d.path);
      if (!st) {
        if (auto f = problem(st.error()); !f) return f;
        continue;
      }
      say(line);
      loaded.push_back(d);
      kept.surfaces.push_back(origin);
    }
    scene.surfaces = std::move(loaded);
  }
  for (const std::string& m : scene.models) {
    if (auto st = renderer.addModel(m); !st)
      if (auto f = problem("--cones: " + st.error()); !f) return f;
  }
  // Map context on by default; missing GSHHG files only warn (the picture still renders).
  if (auto st = renderer.setMapContext(scene.mapContext); !st)
    std::cerr << "warning: " << st.error() << " (drawn without coastlines and borders; --no-map silences this)\n";
  {
    std::vector<engine::MapOverlayDescription> loaded;
    for (std::size_t i = 0; i < scene.overlays.size(); ++i) {
      const engine::MapOverlayDescription& d = scene.overlays[i];
      const std::string origin = engine::layerOrigin(origins.overlays, i, "--overlay");
      Status st = engine::checkInputFile(d.path, keyAt(origin, "path", origin));
      std::string line;
      if (st) {
        auto added = renderer.addOverlay(d);
        if (added) line = *added;
        else st = makeError(origin + ": " + added.error());
      }
      step(d.path);
      if (!st) {
        if (auto f = problem(st.error()); !f) return f;
        continue;
      }
      say(d.path + ": overlay: " + line);
      loaded.push_back(d);
      kept.overlays.push_back(origin);
    }
    scene.overlays = std::move(loaded);
  }
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
