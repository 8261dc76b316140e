#include <atmoglobe/engine/RadarSourceGL.h>

#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Crop.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarLoad.h>
#include <atmoglobe/volume/RadarVolumeSet.h>
#include <atmoglobe/volume/SliceSource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace atmoglobe::engine {

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

// What a GPU volume costs the budget: its CPU twin, its empty-space grid on the CPU, its textures.
std::uint64_t budgetBytes(const RadarVolumeGL& v) {
  const volume::OccupancyGrid& o = v.occupancy().grid();
  return volume::polarVolumeBytes(v.polar()) + (o.maxValues.capacity() + o.blockMaxValues.capacity()) * sizeof(float) +
         v.gpuBytes();
}

// A radar step in the cache: its GPU volume with the time and datum note the layer shows.
// The layer holds the volume through an alias of this entry, so the cache sees it in use.
struct RadarStepGL {
  std::shared_ptr<RadarVolumeGL> volume;
  std::string timeIso8601, datumNote;
};

}  // namespace

// One volume read, cropped, coloured and uploaded: what open and a reload show.
struct RadarShown {
  volume::LoadedRadar radar;
  VolumeRenderOptions options;
  std::unique_ptr<RadarVolumeGL> gl;
};
static Result<RadarShown> loadShown(const VolumeLayerDescription& d, const std::string& files, double exaggeration) {
  auto radar = readCroppedRadar(d, files);
  if (!radar) return radar.forwardError();
  if (isCropped(d.settings) && !(radar->layout->minValue <= radar->layout->maxValue))
    return makeError(d.path + ": the crop box leaves no measured value of " + radar->layout->fieldName);
  auto options = layerRenderOptions(d, radar->volume.loadedField, radar->volume.nyquistVelocityMps,
                                    {radar->layout->minValue, radar->layout->maxValue});
  if (!options) return options.forwardError();
  auto gl = RadarVolumeGL::create(*radar->layout, exaggeration);
  if (!gl) return gl.forwardError();
  (*gl)->setBeamApproximation(d.beam);
  return RadarShown{std::move(*radar), std::move(*options), std::move(*gl)};
}

namespace {

class RadarStepPreparer final : public StepPreparer {
 public:
  RadarStepPreparer(VolumeLayerDescription d, std::vector<std::string> files, double exaggeration)
      : description_(std::move(d)), files_(std::move(files)), exaggeration_(exaggeration) {}
  std::optional<Prepared> prepare(std::size_t step, const PrepareContext&) const override {
    if (step >= files_.size()) return std::nullopt;
    auto data = prepareRadarStep(description_, files_[step]);
    if (!data || !RadarVolumeGL::checkDrawable(data->layout)) return std::nullopt;
    data->prepared = RadarVolumeGL::prepare(data->layout, exaggeration_);  // layers, tables, empty-space grid
    data->layout = volume::PolarVolume{};
    auto shared = std::make_shared<const RadarStepData>(std::move(*data));
    const std::uint64_t bytes = shared->prepared->bytes();
    return Prepared{std::move(shared), bytes};
  }

 private:
  VolumeLayerDescription description_;
  std::vector<std::string> files_;
  double exaggeration_;
};

}  // namespace

Result<RadarStepData> prepareRadarStep(const VolumeLayerDescription& d, const std::string& files) {
  auto radar = readCroppedRadar(d, files);
  if (!radar) return radar.forwardError();
  return RadarStepData{std::move(*radar->layout), radar->volume.timeIso8601, radar->site.datumNote, nullptr};
}

void RadarSourceGL::show(RadarShown loaded) {
  volume_ = std::move(loaded.gl);
  options_ = std::move(loaded.options);
  datumNote_ = loaded.radar.site.datumNote;
  timeIso8601_ = loaded.radar.volume.timeIso8601;
  loadedField_ = loaded.radar.volume.loadedField;
  nyquistMps_ = loaded.radar.volume.nyquistVelocityMps;
  fields_.clear();
  for (const volume::FieldInfo& f : loaded.radar.volume.fields) fields_.push_back(f.name);
}

void RadarSourceGL::cacheShown(volume::StepCache& cache, const std::string& key) {
  auto entry = std::make_shared<RadarStepGL>(RadarStepGL{std::move(volume_), timeIso8601_, datumNote_});
  volume_ = std::shared_ptr<RadarVolumeGL>(entry, entry->volume.get());
  const std::uint64_t bytes = budgetBytes(*entry->volume);
  cache.put(key, std::move(entry), bytes);
}

Result<std::unique_ptr<RadarSourceGL>> RadarSourceGL::open(const VolumeLayerDescription& d, SourceContext context) {
  if (d.kind != VolumeKind::Radar) return makeError(d.path + ": a " + nameOf(d.kind) + " layer is not a radar");
  auto loop = radarLoopSteps(d.path, d.field);
  if (!loop) return loop.forwardError();
  std::unique_ptr<RadarSourceGL> source(new RadarSourceGL());
  // A loop shows its latest volume; the others are steps of the scene's time axis.
  const std::string shown = loop->first.empty() ? d.path : loop->first.back();
  auto loaded = loadShown(d, shown, context.exaggeration);
  if (!loaded) return loaded.forwardError();
  const volume::LoadedRadar& radar = loaded->radar;
  source->siteMarker_.latDeg = radar.site.site.latDeg;
  source->siteMarker_.lonDeg = radar.site.site.lonDeg;
  source->siteMarker_.heightMeters = radar.site.site.antennaHeightEllipsoidMeters;  // exaggerated when drawn
  source->siteMarker_.color = glm::vec3(1.0f, 1.0f, 1.0f);
  source->siteMarker_.sizePx = 12.0f;
  source->siteMarker_.label = d.label.empty() ? radar.volume.site.name : d.label;
  source->siteName_ = volume::siteTitle(radar.volume.site);
  source->synthetic_ = volume::fileSaysSynthetic(shown);
  source->description_ = d;
  source->show(std::move(*loaded));
  source->loopFiles_ = std::move(loop->first);
  source->loopTimes_ = std::move(loop->second);
  source->step_ = source->loopFiles_.empty() ? 0 : source->loopFiles_.size() - 1;
  // The shown volume counts against the memory budget under its step's key.
  source->cacheShown(context.cache, stepKey(context.layer, source->step_, true));
  return source;
}

std::unique_ptr<RadarSourceGL> RadarSourceGL::fromVolume(std::shared_ptr<RadarVolumeGL> volume,
                                                         const VolumeRenderOptions& options, const Marker& siteMarker) {
  std::unique_ptr<RadarSourceGL> source(new RadarSourceGL());
  source->description_.kind = VolumeKind::Radar;
  source->description_.path = volume->polar().sourcePath;
  source->siteName_ = siteMarker.label;
  source->siteMarker_ = siteMarker;
  source->loadedField_.name = volume->polar().fieldName;
  source->fields_ = {volume->polar().fieldName};
  source->volume_ = std::move(volume);
  source->options_ = options;
  return source;
}

std::string RadarSourceGL::title() const { return "radar " + siteMarker_.label + "  " + volume_->polar().fieldName; }

volume::ValueRange RadarSourceGL::colourRange() const {
  return volume::ValueRange{volume_->polar().minValue, volume_->polar().maxValue};
}

volume::ValueHistogram RadarSourceGL::histogram(int bins) const {
  return volume::valueHistogram(volume_->polar(), bins);
}

Status RadarSourceGL::showStep(std::size_t step, double /*fraction: loops show the step's volume*/,
                               SourceContext context) {
  if (step >= loopFiles_.size()) return makeError(description_.path + ": no loop step " + std::to_string(step));
  if (step == step_) return Ok{};
  volume::StepCache& cache = context.cache;
  cache.releaseDropped();  // GPU volumes dropped by a worker's put die here, on the GL thread
  const std::string key = stepKey(context.layer, step, true);
  if (auto cached = cache.get<RadarStepGL>(key)) {
    volume_ = std::shared_ptr<RadarVolumeGL>(cached, cached->volume.get());
    timeIso8601_ = cached->timeIso8601;
    datumNote_ = cached->datumNote;
  } else {
    // Prepared ahead by a ScenePrefetcher, else read now.
    const std::string cpuKey = stepKey(context.layer, step, false);
    cache.waitWhileLoading(cpuKey);  // a background loader's read in flight: wait, do not read twice
    std::shared_ptr<const RadarStepData> data = cache.get<RadarStepData>(cpuKey);
    if (!data) {
      auto read = prepareRadarStep(description_, loopFiles_[step]);
      if (!read) return read.forwardError();
      data = std::make_shared<const RadarStepData>(std::move(*read));
    }
    auto gl = data->prepared ? RadarVolumeGL::create(data->prepared)
                             : RadarVolumeGL::create(data->layout, context.exaggeration);
    if (!gl) return gl.forwardError();
    (*gl)->setBeamApproximation(volume_->beamApproximation());
    volume_ = std::move(*gl);
    timeIso8601_ = data->timeIso8601;
    datumNote_ = data->datumNote;
    cache.erase(cpuKey);  // the GPU volume holds its own copy
    cacheShown(cache, key);
  }
  step_ = step;
  cache.releaseDropped();
  return Ok{};
}

std::unique_ptr<StepPreparer> RadarSourceGL::preparer(double exaggeration) const {
  return std::make_unique<RadarStepPreparer>(description_, loopFiles_, exaggeration);
}

Status RadarSourceGL::setDescription(const VolumeLayerDescription& d, SourceContext context) {
  switch (layerChange(description_, d)) {
    case LayerChange::None: return Ok{};
    case LayerChange::Reload: return reload(d, context);
    case LayerChange::Options: break;
  }
  auto options = layerRenderOptions(d, loadedField_, nyquistMps_, colourRange());
  if (!options) return options.forwardError();
  options_ = std::move(*options);
  volume_->setBeamApproximation(d.beam);
  if (!d.label.empty()) siteMarker_.label = d.label;
  description_ = d;
  return Ok{};
}

Status RadarSourceGL::reload(const VolumeLayerDescription& d, SourceContext context) {
  std::vector<std::string> files = loopFiles_, times = loopTimes_;
  std::size_t step = step_;
  if (d.path != description_.path || d.field != description_.field) {
    auto loop = radarLoopSteps(d.path, d.field);  // another field may sit in other files of the set
    if (!loop) return loop.forwardError();
    if (loop->first.size() != files.size()) step = loop->first.empty() ? 0 : loop->first.size() - 1;
    files = std::move(loop->first);
    times = std::move(loop->second);
  }
  auto loaded = loadShown(d, files.empty() ? d.path : files[step], context.exaggeration);
  if (!loaded) return loaded.forwardError();
  show(std::move(*loaded));
  loopFiles_ = std::move(files);
  loopTimes_ = std::move(times);
  step_ = step;
  if (!d.label.empty()) siteMarker_.label = d.label;
  description_ = d;
  // Every cached step of this layer holds the old field or crop: dropped; the new one cached.
  context.cache.erasePrefix(stepKeyPrefix(context.layer));
  cacheShown(context.cache, stepKey(context.layer, step_, true));
  context.cache.releaseDropped();
  return Ok{};
}

Status RadarSourceGL::applyExaggeration(SourceContext context) {
  auto gl = RadarVolumeGL::create(volume_->polar(), context.exaggeration);  // from the CPU copy: no read
  if (!gl) return gl.forwardError();
  (*gl)->setBeamApproximation(volume_->beamApproximation());
  context.cache.erasePrefix(stepKeyPrefix(context.layer));  // steps cached at the old exaggeration
  volume_ = std::move(*gl);
  cacheShown(context.cache, stepKey(context.layer, step_, true));
  context.cache.releaseDropped();
  return Ok{};
}

LegendPart RadarSourceGL::legendPart() const {
  const volume::PolarVolume& p = volume_->polar();
  const std::string name = siteName_.empty() ? std::string("radar") : siteName_;
  return LegendPart{name + "  " + p.fieldName, name + " volume start " + utcLabel(timeIso8601_),
                    LegendKey{name + " " + p.fieldName, p.fieldUnits, options_.render.transfer.colors}, synthetic_};
}

LayerMemory RadarSourceGL::memory() const {
  const volume::PolarVolume& p = volume_->polar();
  return LayerMemory{"radar " + siteMarker_.label + " " + p.fieldName, p.byteSize(), volume_->gpuBytes()};
}

std::optional<std::string> RadarSourceGL::readoutAt(const glm::dvec3& eye, const glm::dvec3& dir, double tMaxMeters,
                                                    double stepMeters) const {
  // The first gate with an echo along the ray, read as stored (nearest-neighbour sampling), so
  // the value and the gate are those `atmoglobe gates` lists.
  const auto hit =
      firstValueAlong(volume_->referenceSampler(), eye, dir, tMaxMeters, stepMeters, volume::Interpolation::Nearest);
  if (!hit) return std::nullopt;
  const volume::PolarVolume& p = volume_->polar();
  // Antenna coordinates of the true point (the drawn one mapped back under an exaggeration).
  glm::dvec3 trueEcef = hit->ecef;
  if (volume_->exaggeration() != 1.0) {
    globe::Geodetic g = globe::ecefToGeodetic(hit->ecef);
    g.heightMeters /= volume_->exaggeration();
    trueEcef = globe::geodeticToEcef(g);
  }
  const volume::AntennaCoordinates a = volume::antennaCoordinatesExact(p.site, p.beam, trueEcef);
  const auto gate = volume::nearestGate(p, a.rangeMeters, a.azimuthDeg, a.elevationDeg);
  if (!gate) return std::nullopt;  // cannot happen for an echo sample; kept for safety
  const globe::Geodetic g = globe::ecefToGeodetic(trueEcef);
  char text[320];
  std::snprintf(text, sizeof text,
                "%.1f %s  (sweep %.2f deg, azimuth %.1f deg, range %.3f km, height %.0f m above the ellipsoid, "
                "%.0f m above sea level)",
                static_cast<double>(gate->value), p.fieldUnits.c_str(), gate->elevationDeg, gate->azimuthDeg,
                gate->rangeMeters / 1000.0, g.heightMeters, seaLevelHeightMeters(g));
  return (siteName_.empty() ? std::string("radar") : siteName_) + " " + p.fieldName + ": " + text;
}

std::vector<map::GeoPolyline> RadarSourceGL::rangeRings() const {
  return map::rangeRingsAndSpokes(siteMarker_.latDeg, siteMarker_.lonDeg, volume_->polar().maxRangeMeters);
}

}  // namespace atmoglobe::engine
