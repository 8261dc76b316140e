#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/engine/SceneTime.h>

#include "LoaderGL.h"

#include <atmoglobe/engine/LayerEdit.h>
#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/ImageryPyramid.h>
#include <atmoglobe/globe/XyzLayer.h>
#include <atmoglobe/map/GeoLines.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/Crop.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/RadarVolumeSet.h>
#include <atmoglobe/volume/SliceSource.h>
#include <atmoglobe/volume/VerticalExaggeration.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

namespace atmoglobe::engine {

Result<std::shared_ptr<globe::TileImageLoader>> openImagery(const std::vector<ImageryLayerDescription>& layers,
                                                            const globe::TileImageLoaderOptions& options) {
  std::vector<std::shared_ptr<const globe::ImageryLayer>> opened;
  for (const ImageryLayerDescription& d : layers) {
    if (d.type == ImageryLayerDescription::Type::Pyramid) {
      auto layer = globe::GeographicPyramidLayer::open(d.path);
      if (!layer) return layer.forwardError();
      opened.push_back(*layer);
    } else {
      auto layer = globe::XyzMercatorLayer::open(d.path);
      if (!layer) return layer.forwardError();
      opened.push_back(*layer);
    }
  }
  return std::make_shared<globe::TileImageLoader>(std::move(opened), options);
}

Result<volume::TransferFunction> transferForLayer(const std::string& colors, const VolumeLayerSettings& settings,
                                                  const volume::FieldInfo& field, double nyquistMps,
                                                  const volume::ValueRange& range) {
  auto transfer = volume::transferForField(colors, field, nyquistMps, range);
  if (!transfer) return transfer.forwardError();
  volume::TransferFunction t = std::move(*transfer);
  if (settings.valueRange) t = volume::withValueRange(t, settings.valueRange->x, settings.valueRange->y);
  if (!settings.opacity.empty()) t = volume::withOpacityRamp(t, settings.opacity);
  if (settings.opacityPoints.size() >= 2) t = volume::withOpacityPoints(t, settings.opacityPoints);
  return t;
}

namespace {
// The EGM96 grid for crop heights above sea level (null when the layer does not use the geoid).
Result<const volume::GeoidGrid*> cropGeoid(const VolumeLayerSettings& settings, bool useGeoid) {
  if (settings.crop.coversEveryHeight() || !useGeoid) return static_cast<const volume::GeoidGrid*>(nullptr);
  const auto& g = volume::defaultEgm96Grid();
  if (!g) return makeError(g.error());
  return &*g;
}

bool isCropped(const VolumeLayerSettings& settings) {
  return !settings.crop.coversEveryLonLat() || !settings.crop.coversEveryHeight();
}

/// One radar volume (a file, or a set's files) read with its render layout and cut to the
/// layer's crop box: what addRadar, reloadRadar and a loop step load.
Result<volume::LoadedRadar> readCroppedRadar(const VolumeLayerDescription& d, const std::string& files) {
  volume::RadarLoadOptions load;
  load.fieldName = d.field;
  load.useGeoid = d.useGeoid;
  load.buildRenderLayout = true;
  auto radar = volume::loadRadar(files, load);
  if (!radar) return radar.forwardError();
  if (isCropped(d.settings)) {
    auto geoid = cropGeoid(d.settings, d.useGeoid);
    if (!geoid) return makeError(d.path + ": crop heights: " + geoid.error());
    volume::cropPolar(*radar->layout, d.settings.crop, *geoid);
  }
  return radar;
}
}  // namespace

Result<VolumeRenderOptions> layerRenderOptions(const VolumeLayerDescription& d, const volume::FieldInfo& field,
                                               double nyquistMps, const volume::ValueRange& range) {
  VolumeRenderOptions o;
  o.render.mode = d.mode;
  o.render.interpolation = d.interpolation;
  o.render.stepMeters = d.stepMeters;
  o.render.isoValue = d.isoValue.value_or(defaultIsoValue(d.kind, range.minValue, range.maxValue));
  auto transfer = transferForLayer(d.colors, d.settings, field, nyquistMps, range);
  if (!transfer) return transfer.forwardError();
  o.render.transfer = std::move(*transfer);
  o.imageScale = d.imageScale;
  o.classification = d.classification;
  return o;
}

Result<std::unique_ptr<SceneRendererGL>> SceneRendererGL::create(std::shared_ptr<globe::TileImageLoader> loader,
                                                                 const GlobeRenderOptions& globeOptions) {
  std::unique_ptr<SceneRendererGL> r(new SceneRendererGL());
  auto g = GlobeRendererGL::create(std::move(loader), globeOptions);
  if (!g) return g.forwardError();
  r->globe_ = std::move(*g);
  auto m = MarkerRendererGL::create(MarkerStyle::Disc);
  if (!m) return m.forwardError();
  r->markers_ = std::move(*m);
  auto rv = VolumeRendererGL::create();
  if (!rv) return rv.forwardError();
  r->volumeRenderer_ = std::move(*rv);
  auto map = MapRendererGL::create(map::defaultGshhgDirectory());
  if (!map) return map.forwardError();
  r->map_ = std::move(*map);
  return r;
}

Status SceneRendererGL::setMapContext(bool enabled) { return map_->setBuiltinLayers(enabled); }

Result<std::string> SceneRendererGL::addOverlay(const MapOverlayDescription& d) {
  return map_->addOverlay(d.path, MapLineStyle{d.color, d.widthPx, 1.0f});
}

Status SceneRendererGL::addModel(const std::string& glbPath) {
  auto model = GltfModelRendererGL::load(glbPath);
  if (!model) return model.forwardError();
  models_.push_back(std::move(*model));
  return Ok{};
}

Status SceneRendererGL::setVerticalExaggeration(double factor) {
  if (auto st = volume::validateVerticalExaggeration(factor, "scene"); !st) return st;
  if (volumeLayerCount() > 0 || (slices_ && slices_->size() > 0))
    return makeError("the vertical exaggeration must be set before volumes and slices are added");
  exaggeration_ = factor;
  return Ok{};
}

Result<std::string> SceneRendererGL::addSlice(const SliceLayerDescription& d) {
  if (!slices_) {
    auto s = SliceRendererGL::create();
    if (!s) return s.forwardError();
    slices_ = std::move(*s);
  }
  slices_->setVerticalExaggeration(exaggeration_);
  return slices_->add(d);
}

namespace {
// The volumes of a radar loop: a set (directory, glob, list) holding several times of one site.
// Empty when `path` is one file or one volume. Metadata only.
Result<std::pair<std::vector<std::string>, std::vector<std::string>>> radarLoopSteps(const std::string& path,
                                                                                     const std::string& field) {
  std::pair<std::vector<std::string>, std::vector<std::string>> out;
  if (!volume::isRadarFileSet(path)) return out;
  auto paths = volume::expandRadarPaths(path);
  if (!paths) return paths.forwardError();
  volume::RadarSetOptions o;
  o.read.loadValues = false;
  o.read.fieldName = field;
  auto groups = volume::readRadarVolumeGroups(*paths, o);
  if (!groups || groups->size() < 2) return out;  // one volume (or an error loadRadar reports)
  for (const auto& g : *groups) {
    if (std::abs(g.site.latDeg - groups->front().site.latDeg) > 0.01 ||
        std::abs(g.site.lonDeg - groups->front().site.lonDeg) > 0.01)
      return out;  // several sites: not a loop (loadRadar says why)
  }
  std::vector<const volume::RadarVolume*> byTime;
  for (const auto& g : *groups) byTime.push_back(&g);
  std::stable_sort(byTime.begin(), byTime.end(),
                   [](const auto* a, const auto* b) { return a->timeIso8601 < b->timeIso8601; });
  for (const auto* g : byTime) {
    std::string files;
    for (const std::string& f : g->sourceFiles) files += (files.empty() ? "" : ",") + f;
    if (files.empty()) files = g->sourcePath;
    out.first.push_back(files);
    out.second.push_back(g->timeIso8601);
  }
  return out;
}
}  // namespace

namespace {
// What a GPU volume costs the budget: its CPU twin, its empty-space grid on the CPU, its textures.
std::uint64_t occupancyHostBytes(const VolumeGL& v) {
  const volume::OccupancyGrid& o = v.occupancy().grid();
  return (o.maxValues.capacity() + o.blockMaxValues.capacity()) * sizeof(float);
}
std::uint64_t budgetBytes(const GridVolumeGL& v) {
  return volume::gridVolumeBytes(v.grid()) + occupancyHostBytes(v) + v.gpuBytes();
}
std::uint64_t budgetBytes(const RadarVolumeGL& v) {
  return volume::polarVolumeBytes(v.polar()) + occupancyHostBytes(v) + v.gpuBytes();
}

// A radar step in the cache: its GPU volume with the time and datum note the layer shows.
// The layer holds the volume through an alias of this entry, so the cache sees it in use.
struct RadarStepGL {
  std::shared_ptr<RadarVolumeGL> volume;
  std::string timeIso8601, datumNote;
};
void cacheRadarStep(volume::StepCache& cache, RadarLayerGL& layer, const std::string& key) {
  auto entry = std::make_shared<RadarStepGL>(RadarStepGL{std::move(layer.volume), layer.timeIso8601, layer.datumNote});
  layer.volume = std::shared_ptr<RadarVolumeGL>(entry, entry->volume.get());
  const std::uint64_t bytes = budgetBytes(*entry->volume);
  cache.put(key, std::move(entry), bytes);
}
}  // namespace

Status SceneRendererGL::addVolume(const VolumeLayerDescription& d) {
  if (d.kind == VolumeKind::Radar) {
    auto layer = addRadar(d);
    return layer ? Status(Ok{}) : layer.forwardError();
  }
  auto layer = addGrid(d);
  return layer ? Status(Ok{}) : layer.forwardError();
}

Result<const RadarLayerGL*> SceneRendererGL::addRadar(const VolumeLayerDescription& d) {
  if (d.kind != VolumeKind::Radar) return makeError(d.path + ": addRadar of a " + nameOf(d.kind) + " layer");
  auto loop = radarLoopSteps(d.path, d.field);
  if (!loop) return loop.forwardError();
  if (!loop->first.empty()) {
    // A loop: show the latest volume; the others are steps of the scene's time axis.
    VolumeLayerDescription latest = d;
    latest.path = loop->first.back();
    auto layer = addRadar(latest);
    if (!layer) return layer;
    RadarLayerGL& added = radars_.back();
    added.description = d;
    added.loopFiles = std::move(loop->first);
    added.loopTimes = std::move(loop->second);
    added.step = added.loopFiles.size() - 1;
    // The shown volume counts against the memory budget under its step's key.
    cache_->erase(stepKey(true, radars_.size() - 1, 0, true));
    cacheRadarStep(*cache_, added, stepKey(true, radars_.size() - 1, added.step, true));
    return &added;
  }
  auto radar = readCroppedRadar(d, d.path);
  if (!radar) return radar.forwardError();
  if (isCropped(d.settings) && !(radar->layout->minValue <= radar->layout->maxValue))
    return makeError(d.path + ": the crop box leaves no measured value of " + radar->layout->fieldName);
  auto options = layerRenderOptions(d, radar->volume.loadedField, radar->volume.nyquistVelocityMps,
                                    {radar->layout->minValue, radar->layout->maxValue});
  if (!options) return options.forwardError();
  auto gl = RadarVolumeGL::create(*radar->layout, exaggeration_);
  if (!gl) return gl.forwardError();
  (*gl)->setBeamApproximation(d.beam);
  RadarLayerGL layer;
  layer.volume = std::move(*gl);
  layer.options = *options;
  layer.datumNote = radar->site.datumNote;
  layer.siteMarker.latDeg = radar->site.site.latDeg;
  layer.siteMarker.lonDeg = radar->site.site.lonDeg;
  layer.siteMarker.heightMeters = radar->site.site.antennaHeightEllipsoidMeters;  // exaggerated when drawn
  layer.siteMarker.color = glm::vec3(1.0f, 1.0f, 1.0f);
  layer.siteMarker.sizePx = 12.0f;
  layer.siteMarker.label = d.label.empty() ? radar->volume.site.name : d.label;
  layer.siteName = radar->volume.site.name;
  layer.timeIso8601 = radar->volume.timeIso8601;
  layer.synthetic = volume::fileSaysSynthetic(d.path);
  layer.description = d;
  for (const volume::FieldInfo& f : radar->volume.fields) layer.fields.push_back(f.name);
  layer.loadedField = radar->volume.loadedField;
  layer.nyquistMps = radar->volume.nyquistVelocityMps;
  radars_.push_back(std::move(layer));
  cacheRadarStep(*cache_, radars_.back(), stepKey(true, radars_.size() - 1, 0, true));
  return &radars_.back();
}

namespace {
// The crop box's cut of a grid as read (the reader already kept only the box's columns and one
// more on each side; heights and the exact box are cut here).
Status cropGridLayer(const VolumeLayerDescription& d, volume::GridVolume& grid) {
  if (d.settings.crop.coversEveryLonLat() && d.settings.crop.coversEveryHeight()) return Ok{};
  auto geoid = cropGeoid(d.settings, d.useGeoid);
  if (!geoid) return makeError(d.path + ": crop heights: " + geoid.error());
  volume::cropGrid(grid, d.settings.crop, *geoid);
  if (!(grid.valueMin <= grid.valueMax))
    return makeError(d.path + ": the crop box leaves no value of " + grid.variable);
  return Ok{};
}

// What a grid layer reads: its variable, crop and datum (the time step is set by the caller).
volume::GridReadOptions gridReadOptions(const VolumeLayerDescription& d) {
  volume::GridReadOptions read;
  read.variable = d.field;
  read.useGeoid = d.useGeoid;
  read.crop.southDeg = d.settings.crop.southDeg;
  read.crop.northDeg = d.settings.crop.northDeg;
  read.crop.westDeg = d.settings.crop.westDeg;
  read.crop.eastDeg = d.settings.crop.eastDeg;
  return read;
}
}  // namespace

namespace {
// A grid layer's render options; colours over `range` (the values of the step first loaded).
Result<VolumeRenderOptions> gridRenderOptions(const VolumeLayerDescription& d, const volume::GridVolume& grid,
                                              const volume::ValueRange& range) {
  return layerRenderOptions(d, volume::FieldInfo{grid.variable, grid.units, grid.standardName},
                            std::numeric_limits<double>::quiet_NaN(), range);
}
}  // namespace

Result<const GridLayerGL*> SceneRendererGL::addGrid(const VolumeLayerDescription& d) {
  if (d.kind != VolumeKind::Grid) return makeError(d.path + ": addGrid of a " + nameOf(d.kind) + " layer");
  volume::GridReadOptions read = gridReadOptions(d);
  if (auto st = volume::selectGridTime(d.time, read); !st) return makeError(d.path + ": " + st.error());
  auto grid = volume::readGridVolume(d.path, read);
  if (!grid) return grid.forwardError();
  if (auto st = cropGridLayer(d, *grid); !st) return st.forwardError();
  const volume::ValueRange range{grid->valueMin, grid->valueMax};
  if (!(range.minValue <= range.maxValue))
    return makeError(d.path + ": " + grid->variable + " has no valid value at " +
                     (grid->validTime.empty() ? std::string("the step read") : grid->validTime));
  auto o = gridRenderOptions(d, *grid, range);
  if (!o) return o.forwardError();
  volume::exaggerateGrid(*grid, exaggeration_);
  auto gl = GridVolumeGL::create(*grid);
  if (!gl) return gl.forwardError();
  GridLayerGL layer;
  layer.volume = std::move(*gl);
  layer.options = std::move(*o);
  layer.description = d;
  layer.step = grid->timeIndex;
  layer.synthetic = volume::fileSaysSynthetic(d.path);
  layer.firstRange = range;
  grids_.push_back(std::move(layer));
  const GridVolumeGL& shown = *grids_.back().volume;
  cache_->put(stepKey(false, grids_.size() - 1, grid->timeIndex, true), grids_.back().volume, budgetBytes(shown));
  return &grids_.back();
}

Result<RadarStepData> prepareRadarStep(const VolumeLayerDescription& d, const std::string& files) {
  auto radar = readCroppedRadar(d, files);
  if (!radar) return radar.forwardError();
  return RadarStepData{std::move(*radar->layout), radar->volume.timeIso8601, radar->site.datumNote, nullptr};
}

Result<volume::GridVolume> prepareGridStep(const VolumeLayerDescription& d, std::size_t step, double exaggeration) {
  volume::GridReadOptions read = gridReadOptions(d);
  read.timeIndex = step;
  auto grid = volume::readGridVolume(d.path, read);
  if (!grid) return grid.forwardError();
  if (auto st = cropGridLayer(d, *grid); !st) return st.forwardError();
  volume::exaggerateGrid(*grid, exaggeration);
  return grid;
}

Status SceneRendererGL::setRadarStep(std::size_t index, std::size_t step) {
  if (index >= radars_.size()) return makeError("no radar layer " + std::to_string(index));
  RadarLayerGL& layer = radars_[index];
  if (step >= layer.loopFiles.size())
    return makeError(layer.description.path + ": no loop step " + std::to_string(step));
  if (step == layer.step) return Ok{};
  cache_->releaseDropped();  // GPU volumes dropped by a worker's put die here, on the GL thread
  const std::string key = stepKey(true, index, step, true);
  if (auto cached = cache_->get<RadarStepGL>(key)) {
    layer.volume = std::shared_ptr<RadarVolumeGL>(cached, cached->volume.get());
    layer.timeIso8601 = cached->timeIso8601;
    layer.datumNote = cached->datumNote;
  } else {
    // Prepared ahead by a ScenePrefetcher, else read now.
    const std::string cpuKey = stepKey(true, index, step, false);
    cache_->waitWhileLoading(cpuKey);  // a background loader's read in flight: wait, do not read twice
    std::shared_ptr<const RadarStepData> data = cache_->get<RadarStepData>(cpuKey);
    if (!data) {
      auto read = prepareRadarStep(layer.description, layer.loopFiles[step]);
      if (!read) return read.forwardError();
      data = std::make_shared<const RadarStepData>(std::move(*read));
    }
    auto gl = data->prepared ? RadarVolumeGL::create(data->prepared)
                             : RadarVolumeGL::create(data->layout, exaggeration_);
    if (!gl) return gl.forwardError();
    (*gl)->setBeamApproximation(layer.volume->beamApproximation());
    layer.volume = std::move(*gl);
    layer.timeIso8601 = data->timeIso8601;
    layer.datumNote = data->datumNote;
    cache_->erase(cpuKey);  // the GPU volume holds its own copy
    cacheRadarStep(*cache_, layer, key);
  }
  layer.step = step;
  cache_->releaseDropped();
  return Ok{};
}

Result<std::shared_ptr<const GridVolumeGL::Prepared>> SceneRendererGL::gridStepPrepared(std::size_t index,
                                                                                        std::size_t step) {
  const std::string cpuKey = stepKey(false, index, step, false);
  cache_->waitWhileLoading(cpuKey);  // a background loader's read in flight: wait, do not read twice
  if (auto cpu = cache_->get<GridVolumeGL::Prepared>(cpuKey)) return cpu;
  auto grid = prepareGridStep(grids_[index].description, step, exaggeration_);
  if (!grid) return grid.forwardError();
  if (auto st = GridVolumeGL::checkDrawable(*grid); !st) return st.forwardError();
  auto prepared = GridVolumeGL::prepare(*grid);
  cache_->put(cpuKey, prepared, prepared->bytes());
  return prepared;
}

Result<std::shared_ptr<const volume::GridVolume>> SceneRendererGL::gridStepData(std::size_t index, std::size_t step) {
  if (auto gl = cache_->get<GridVolumeGL>(stepKey(false, index, step, true)))
    return std::shared_ptr<const volume::GridVolume>(gl, &gl->grid());
  auto prepared = gridStepPrepared(index, step);
  if (!prepared) return prepared.forwardError();
  return std::shared_ptr<const volume::GridVolume>(*prepared, (*prepared)->grid.get());
}

Status SceneRendererGL::setGridStep(std::size_t index, std::size_t step, double fraction) {
  if (index >= grids_.size()) return makeError("no grid layer " + std::to_string(index));
  GridLayerGL& layer = grids_[index];
  if (!(fraction >= 0.0 && fraction < 1.0)) return makeError(layer.description.path + ": time fraction outside [0, 1)");
  if (layer.step == step && layer.stepFraction == fraction) return Ok{};
  cache_->releaseDropped();  // GPU volumes dropped by a worker's put die here, on the GL thread
  const std::string key = stepKey(false, index, step, true, fraction);
  if (auto cached = cache_->get<GridVolumeGL>(key)) {
    layer.volume = std::const_pointer_cast<GridVolumeGL>(cached);
  } else {
    Result<std::unique_ptr<GridVolumeGL>> gl = makeError("");
    if (fraction == 0.0) {
      // Prepared ahead by a ScenePrefetcher (only the upload is left), else read and prepared now.
      auto prepared = gridStepPrepared(index, step);
      if (!prepared) return prepared.forwardError();
      gl = GridVolumeGL::create(std::move(*prepared));
    } else {
      auto grid = gridStepData(index, step);
      if (!grid) return grid.forwardError();
      auto next = gridStepData(index, step + 1);
      if (!next) return next.forwardError();
      auto blended = volume::interpolateGridSteps(**grid, **next, fraction);
      if (!blended) return blended.forwardError();
      gl = GridVolumeGL::create(*blended);
    }
    if (!gl) return gl.forwardError();
    layer.volume = std::move(*gl);
    // A whole step's CPU data now live in its GPU volume's twin (interpolation keeps both ends).
    if (fraction == 0.0) cache_->erase(stepKey(false, index, step, false));
    cache_->put(key, layer.volume, budgetBytes(*layer.volume));
  }
  layer.step = step;
  layer.stepFraction = fraction;
  cache_->releaseDropped();
  return Ok{};
}

/// A grid read afresh with description `d` (the panel changed its variable, crop or the scene's
/// exaggeration): every cached step of this layer is stale and dropped; the new one is cached.
Status SceneRendererGL::reloadGrid(std::size_t index, const VolumeLayerDescription& d, std::size_t step,
                                   double fraction) {
  GridLayerGL& layer = grids_[index];
  volume::GridReadOptions read = gridReadOptions(d);
  read.timeIndex = step;
  auto grid = volume::readGridVolume(d.path, read);
  if (!grid) return grid.forwardError();
  if (auto st = cropGridLayer(d, *grid); !st) return st.forwardError();
  if (fraction > 0.0) {
    read.timeIndex = step + 1;
    auto next = volume::readGridVolume(d.path, read);
    if (!next) return next.forwardError();
    if (auto st = cropGridLayer(d, *next); !st) return st.forwardError();
    auto blended = volume::interpolateGridSteps(*grid, *next, fraction);
    if (!blended) return blended.forwardError();
    grid = std::move(blended);
  }
  volume::exaggerateGrid(*grid, exaggeration_);
  auto gl = GridVolumeGL::create(*grid);
  if (!gl) return gl.forwardError();
  cache_->erasePrefix(stepKeyPrefix(false, index));
  layer.volume = std::move(*gl);
  layer.step = step;
  layer.stepFraction = fraction;
  cache_->put(stepKey(false, index, step, true, fraction), layer.volume, budgetBytes(*layer.volume));
  cache_->releaseDropped();
  return Ok{};
}

SceneFrameStats SceneRendererGL::renderFrame(const Camera& camera, const std::vector<Marker>& markers,
                                             const FramebufferGL& target) {
  const auto start = std::chrono::steady_clock::now();
  SceneFrameStats stats;
  target.bind();
  // Reverse-Z: depth = near / distance in [0, 1]; 0 is infinitely far.
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glClearDepth(0.0);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_CULL_FACE);
  stats.globe = globe_->draw(camera);
  for (const auto& model : models_) model->draw(camera);
  if (slices_) slices_->draw(camera);  // before the volumes: the march stops at their depth
  for (; rangeRings_ && radarsWithRings_ < radars_.size(); ++radarsWithRings_) {
    const RadarLayerGL& radar = radars_[radarsWithRings_];
    map_->addLines(map::rangeRingsAndSpokes(radar.siteMarker.latDeg, radar.siteMarker.lonDeg,
                                            radar.volume->polar().maxRangeMeters),
                   MapLineStyle{glm::vec3(0.95f, 0.9f, 0.55f), 1.0f, 0.7f});
  }
  stats.map = map_->draw(camera);  // writes no depth: the march sees the globe's
  // Every radar in one draw: where volumes overlap, the march integrates them together.
  std::vector<Marker> all = markers;
  std::vector<VolumeLayerGL> layers;
  for (std::size_t i : volumeOrder()) {  // the panel's order; layers switched off are left out
    if (i < radars_.size()) {
      const RadarLayerGL& radar = radars_[i];
      if (!radar.visible) continue;
      layers.push_back(VolumeLayerGL{radar.volume.get(), radar.options});
      all.push_back(radar.siteMarker);
    } else if (const GridLayerGL& grid = grids_[i - radars_.size()]; grid.visible) {
      layers.push_back(VolumeLayerGL{grid.volume.get(), grid.options});
    }
  }
  if (!layers.empty() && referenceThreads_ > 0) {
    const auto t0 = std::chrono::steady_clock::now();
    volumeRenderer_->drawReference(camera, layers, target, referenceThreads_);
    stats.referenceSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } else if (!layers.empty()) {
    volumeRenderer_->draw(camera, layers, target);
  }
  if (exaggeration_ != 1.0)
    for (Marker& m : all) m.heightMeters *= exaggeration_;
  markers_->draw(camera, all);
  stats.cpuMilliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

Result<globe::ImageRGBA8> SceneRendererGL::renderToImage(const Camera& camera, const std::vector<Marker>& markers,
                                                         FramebufferGL& target, int maxPasses,
                                                         SceneFrameStats* lastStats) {
  if (camera.widthPx() != target.widthPx() || camera.heightPx() != target.heightPx()) {
    return makeError("camera image size does not match the render target");
  }
  SceneFrameStats stats;
  // Bring the imagery in with globe-only passes (cheap), then draw the whole frame once.
  for (int pass = 0; pass < maxPasses; ++pass) {
    target.bind();
    stats.globe = globe_->draw(camera);
    if (globe_->lastFrameComplete()) break;
    globe_->loader().waitIdle();  // decoding happens on the loader's threads
  }
  stats = renderFrame(camera, markers, target);
  glFinish();
  if (lastStats) *lastStats = stats;
  for (const std::string& e : globe_->loader().takeErrors()) {
    return makeError("imagery: " + e);
  }
  return target.readColor();
}

FrameLegend SceneRendererGL::legendFor(const Camera& camera) const {
  FrameLegend legend;
  std::string what;
  auto add = [&](const std::string& s) { what += (what.empty() ? "" : "  |  ") + s; };
  for (const RadarLayerGL& r : radars_) {
    if (!r.visible) continue;
    const volume::PolarVolume& p = r.volume->polar();
    const std::string name = r.siteName.empty() ? std::string("radar") : r.siteName;
    add(name + "  " + p.fieldName);
    legend.subtitles.push_back(name + " volume start " + utcLabel(r.timeIso8601));
    legend.keys.push_back(LegendKey{name + " " + p.fieldName, p.fieldUnits, r.options.render.transfer.colors});
    legend.synthetic = legend.synthetic || r.synthetic;
  }
  for (const GridLayerGL& g : grids_) {
    if (!g.visible) continue;
    const volume::GridVolume& v = g.volume->grid();
    std::string variable = v.variable;
    if (!variable.empty() && variable.front() == '/') variable.erase(0, 1);
    add(variable + " (forecast grid)");
    legend.subtitles.push_back(variable + " valid " + utcLabel(v.validTime) +
                               (v.approximateHeights ? "  (heights approximate)" : ""));
    legend.keys.push_back(LegendKey{variable, v.units, g.options.render.transfer.colors});
    legend.synthetic = legend.synthetic || g.synthetic;
  }
  legend.title = what;
  if (exaggeration_ != 1.0) legend.subtitles.push_back("vertical exaggeration x" + fixed(exaggeration_, 1));
  // Scale at the image centre: the ground distance one pixel spans there.
  const glm::dvec3 dir = camera.pixelRayDirection(0.5 * camera.widthPx(), 0.5 * camera.heightPx());
  if (auto hit = globe::intersectRayEllipsoid(camera.eyeEcef(), dir)) {
    legend.metersPerPixel = glm::length(*hit - camera.eyeEcef()) / camera.focalLengthPx();
  }
  return legend;
}

// --- Live edits (the control panel) ---

const VolumeLayerDescription& SceneRendererGL::volumeDescription(std::size_t index) const {
  return index < radars_.size() ? radars_[index].description : grids_[index - radars_.size()].description;
}

Status SceneRendererGL::setVolumeDescription(std::size_t index, const VolumeLayerDescription& d) {
  if (index >= volumeLayerCount()) return makeError("no volume layer " + std::to_string(index));
  if (d.kind != volumeDescription(index).kind)
    return makeError(d.path + ": a " + nameOf(volumeDescription(index).kind) + " layer cannot become a " +
                     nameOf(d.kind));
  if (auto st = validateVolumeLayer(d, d.path); !st) return st;
  return d.kind == VolumeKind::Radar ? setRadarDescription(index, d) : setGridDescription(index - radars_.size(), d);
}

Status SceneRendererGL::setRadarDescription(std::size_t index, const VolumeLayerDescription& d) {
  RadarLayerGL& layer = radars_[index];
  switch (layerChange(layer.description, d)) {
    case LayerChange::None: return Ok{};
    case LayerChange::Reload: return reloadRadar(index, d);
    case LayerChange::Options: break;
  }
  const volume::PolarVolume& p = layer.volume->polar();
  auto options = layerRenderOptions(d, layer.loadedField, layer.nyquistMps, {p.minValue, p.maxValue});
  if (!options) return options.forwardError();
  layer.options = std::move(*options);
  layer.volume->setBeamApproximation(d.beam);
  if (!d.label.empty()) layer.siteMarker.label = d.label;
  layer.description = d;
  return Ok{};
}

Status SceneRendererGL::reloadRadar(std::size_t index, const VolumeLayerDescription& d) {
  RadarLayerGL& layer = radars_[index];
  std::vector<std::string> files = layer.loopFiles, times = layer.loopTimes;
  std::size_t step = layer.step;
  if (d.path != layer.description.path || d.field != layer.description.field) {
    auto loop = radarLoopSteps(d.path, d.field);  // another field may sit in other files of the set
    if (!loop) return loop.forwardError();
    if (loop->first.size() != files.size()) step = loop->first.empty() ? 0 : loop->first.size() - 1;
    files = std::move(loop->first);
    times = std::move(loop->second);
  }
  auto radar = readCroppedRadar(d, files.empty() ? d.path : files[step]);
  if (!radar) return radar.forwardError();
  if (isCropped(d.settings) && !(radar->layout->minValue <= radar->layout->maxValue))
    return makeError(d.path + ": the crop box leaves no measured value of " + radar->layout->fieldName);
  auto options = layerRenderOptions(d, radar->volume.loadedField, radar->volume.nyquistVelocityMps,
                                    {radar->layout->minValue, radar->layout->maxValue});
  if (!options) return options.forwardError();
  auto gl = RadarVolumeGL::create(*radar->layout, exaggeration_);
  if (!gl) return gl.forwardError();
  (*gl)->setBeamApproximation(d.beam);
  layer.volume = std::move(*gl);
  layer.options = std::move(*options);
  layer.datumNote = radar->site.datumNote;
  layer.timeIso8601 = radar->volume.timeIso8601;
  layer.loadedField = radar->volume.loadedField;
  layer.nyquistMps = radar->volume.nyquistVelocityMps;
  layer.fields.clear();
  for (const volume::FieldInfo& f : radar->volume.fields) layer.fields.push_back(f.name);
  layer.loopFiles = std::move(files);
  layer.loopTimes = std::move(times);
  layer.step = step;
  if (!d.label.empty()) layer.siteMarker.label = d.label;
  layer.description = d;
  // Every cached step of this layer holds the old field or crop: dropped; the new one cached.
  cache_->erasePrefix(stepKeyPrefix(true, index));
  cacheRadarStep(*cache_, layer, stepKey(true, index, step, true));
  cache_->releaseDropped();
  return Ok{};
}

Status SceneRendererGL::setGridDescription(std::size_t index, const VolumeLayerDescription& d) {
  GridLayerGL& layer = grids_[index];
  switch (layerChange(layer.description, d)) {
    case LayerChange::None: return Ok{};
    case LayerChange::Reload: {
      VolumeLayerDescription previous = layer.description;
      volume::ValueRange previousRange = layer.firstRange;
      if (d.field != previous.field || d.path != previous.path) layer.firstRange = {};  // new colours' range
      if (auto st = reloadGrid(index, d, layer.step, layer.stepFraction); !st) {
        layer.firstRange = previousRange;
        return st;
      }
      if (!(layer.firstRange.minValue < layer.firstRange.maxValue)) {
        const volume::GridVolume& g = layer.volume->grid();
        layer.firstRange = {g.valueMin, g.valueMax};
      }
      break;
    }
    case LayerChange::Options: break;
  }
  auto o = gridRenderOptions(d, layer.volume->grid(), layer.firstRange);
  if (!o) return o.forwardError();
  layer.options = std::move(*o);
  layer.description = d;
  return Ok{};
}

Status SceneRendererGL::changeVerticalExaggeration(double factor) {
  if (auto st = volume::validateVerticalExaggeration(factor, "scene"); !st) return st;
  if (factor == exaggeration_) return Ok{};
  if (slices_ && slices_->size() > 0)
    return makeError("the scene has slices: its vertical exaggeration is fixed when they are sampled");
  const double previous = exaggeration_;
  exaggeration_ = factor;
  cache_->erasePrefix("radar:");  // radar steps cached at the old exaggeration (reloadGrid drops grids')
  for (RadarLayerGL& layer : radars_) {
    auto gl = RadarVolumeGL::create(layer.volume->polar(), factor);  // from the CPU copy: no read
    if (!gl) {
      exaggeration_ = previous;
      return gl.forwardError();
    }
    (*gl)->setBeamApproximation(layer.volume->beamApproximation());
    layer.volume = std::move(*gl);
    const auto index = static_cast<std::size_t>(&layer - radars_.data());
    cacheRadarStep(*cache_, layer, stepKey(true, index, layer.step, true));
  }
  cache_->releaseDropped();
  for (std::size_t i = 0; i < grids_.size(); ++i) {
    if (auto st = reloadGrid(i, grids_[i].description, grids_[i].step, grids_[i].stepFraction); !st) return st;
  }
  return Ok{};
}

Status SceneRendererGL::setVolumeOrder(const std::vector<std::size_t>& order) {
  std::vector<std::size_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i)
    if (sorted[i] != i) return makeError("the volume order is not a permutation of the layers");
  if (sorted.size() != volumeLayerCount()) return makeError("the volume order must name every layer once");
  volumeOrder_ = order;
  return Ok{};
}

std::vector<std::size_t> SceneRendererGL::volumeOrder() const {
  if (volumeOrder_.size() == volumeLayerCount()) return volumeOrder_;
  std::vector<std::size_t> order(volumeLayerCount());  // layers added since: radars, then grids
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  return order;
}

std::vector<LayerMemory> SceneRendererGL::layerMemory() const {
  std::vector<LayerMemory> out;
  for (const RadarLayerGL& r : radars_) {
    const volume::PolarVolume& p = r.volume->polar();
    out.push_back(LayerMemory{"radar " + r.siteMarker.label + " " + p.fieldName, p.byteSize(), r.volume->gpuBytes()});
  }
  for (const GridLayerGL& g : grids_) {
    const volume::GridVolume& v = g.volume->grid();
    const std::uint64_t cpu = (v.values.size() + v.heightAboveEllipsoidMeters.size()) * sizeof(float) +
                              (v.lonDeg.size() + v.latDeg.size()) * sizeof(double);
    out.push_back(LayerMemory{"grid " + v.variable, cpu, g.volume->gpuBytes()});
  }
  return out;
}

}  // namespace atmoglobe::engine
