#include <atmoglobe/engine/RadarNetworkSourceGL.h>

#include <atmoglobe/globe/ParallelFor.h>

#include <atmoglobe/engine/RadarSourceGL.h>
#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/RadarVolumeSet.h>
#include <atmoglobe/volume/SliceSource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <span>

namespace atmoglobe::engine {

namespace {

constexpr double kSameStepSeconds = 60.0;  // volume times this close are one step of the network

// The volumes of a set by site (metadata only): empty when the set holds one site or is one file.
Result<std::vector<volume::RadarVolume>> volumesOfSet(const std::string& path, const std::string& field) {
  std::vector<volume::RadarVolume> none;
  if (!volume::isRadarFileSet(path)) return none;
  auto paths = volume::expandRadarPaths(path);
  if (!paths) return paths.forwardError();
  volume::RadarSetOptions o;
  o.read.loadValues = false;
  o.read.fieldName = field;
  return volume::readRadarVolumeGroups(*paths, o);
}

bool sameSite(const volume::RadarVolume& a, const volume::RadarVolume& b) {
  return std::abs(a.site.latDeg - b.site.latDeg) <= 0.01 && std::abs(a.site.lonDeg - b.site.lonDeg) <= 0.01;
}

// What a volume of the step costs the budget per gate before it is read: its float on the CPU and
// its RGBA16F texel (value, echo, measured) on the GPU. An upper bound: a crop keeps fewer gates.
constexpr std::uint64_t kBudgetBytesPerGate = sizeof(float) + 4 * 2;

// The cache key of a volume read for the network layer `layer` (by its files: steps share them).
std::string volumeKey(std::size_t layer, const std::string& files) { return stepKeyPrefix(layer) + "volume:" + files; }
// The key of its upload parts (RadarNetworkGL::prepareRadar).
std::string partsKey(std::size_t layer, const std::string& files) { return volumeKey(layer, files) + ":parts"; }

std::string mib(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / 1048576.0);
  return text;
}

// Values of different sites that cannot be combined: drawn per radar unless a rule is asked for.
bool perRadarQuantity(volume::FieldKind kind) {
  return kind == volume::FieldKind::Velocity || kind == volume::FieldKind::DifferentialPhase;
}

// The layer's overlap rule for a field: the one it names, else per radar (integrate) for values
// that cannot be combined and the weighted mean for the others.
volume::OverlapRule overlapRuleOf(const VolumeLayerDescription& d, const volume::FieldInfo& field) {
  return d.overlap.value_or(perRadarQuantity(volume::classifyField(field).kind) ? volume::OverlapRule::Integrate
                                                                                : volume::OverlapRule::WeightedMean);
}

}  // namespace

Result<std::unique_ptr<RadarNetworkSourceGL>> RadarNetworkSourceGL::openIfNetwork(const VolumeLayerDescription& d,
                                                                                  SourceContext context) {
  if (d.kind != VolumeKind::Radar)
    return makeError(d.path + ": a " + std::string(nameOf(d.kind)) + " layer is not a radar");
  auto groups = volumesOfSet(d.path, d.field);
  if (!groups) return groups.forwardError();
  if (std::all_of(groups->begin(), groups->end(), [&](const auto& g) { return sameSite(g, groups->front()); }))
    return std::unique_ptr<RadarNetworkSourceGL>();  // one file, or one site's volumes: not a network
  std::unique_ptr<RadarNetworkSourceGL> s(new RadarNetworkSourceGL());
  // Sites (a volume joins the site within 0.01 deg of its position) and the steps: the distinct
  // volume times.
  std::vector<double> epochs;
  for (const volume::RadarVolume& g : *groups) {
    auto site = std::find_if(s->sites_.begin(), s->sites_.end(), [&](const Site& x) {
      return std::abs(g.site.latDeg - x.latDeg) <= 0.01 && std::abs(g.site.lonDeg - x.lonDeg) <= 0.01;
    });
    if (site == s->sites_.end()) {
      Site added;
      added.name = volume::siteTitle(g.site);
      added.latDeg = g.site.latDeg;
      added.lonDeg = g.site.lonDeg;
      s->sites_.push_back(std::move(added));
      site = s->sites_.end() - 1;
    }
    SiteVolume v;
    for (const std::string& f : g.sourceFiles) v.files += (v.files.empty() ? "" : ",") + f;
    if (v.files.empty()) v.files = g.sourcePath;
    v.timeIso8601 = g.timeIso8601;
    for (const volume::Sweep& sweep : g.sweeps) v.gates += std::uint64_t{sweep.rayCount()} * sweep.gateCount;
    v.epochSeconds = volume::iso8601ToEpochSeconds(g.timeIso8601);
    if (!std::isfinite(v.epochSeconds))
      return makeError(v.files + ": a radar network needs each volume's time, and this one has none");
    epochs.push_back(v.epochSeconds);
    site->volumes.push_back(std::move(v));
  }
  for (Site& site : s->sites_)
    std::stable_sort(site.volumes.begin(), site.volumes.end(),
                     [](const SiteVolume& a, const SiteVolume& b) { return a.epochSeconds < b.epochSeconds; });
  std::sort(epochs.begin(), epochs.end());
  // A step at the last time of each run of times less than a minute apart.
  for (std::size_t i = 0; i < epochs.size(); ++i) {
    if (i + 1 < epochs.size() && epochs[i + 1] - epochs[i] < kSameStepSeconds) continue;
    s->stepEpochs_.push_back(epochs[i]);
  }
  for (double e : s->stepEpochs_) {
    // The step's label: the time of a volume at it (all volumes carry ISO times).
    std::string label;
    for (const Site& site : s->sites_)
      for (const SiteVolume& v : site.volumes)
        if (v.epochSeconds == e) label = v.timeIso8601;
    s->times_.push_back(volume::normalizeIso8601(label));
  }
  s->description_ = d;
  if (auto st = s->load(d, s->stepEpochs_.size() - 1, context); !st) return st.forwardError();
  s->step_ = s->stepEpochs_.size() - 1;
  return s;
}

std::uint64_t RadarNetworkSourceGL::StepGL::apartBytes() const {
  std::uint64_t bytes = 0;
  for (const auto& r : apart) bytes += r->gpuBytes() + volume::polarVolumeBytes(r->polar());  // with its own copy
  return bytes;
}

std::uint64_t RadarNetworkSourceGL::StepGL::gpuBytes() const {
  std::uint64_t bytes = apartBytes();
  for (const auto& c : clusters) bytes += c->gpuBytes();
  return bytes;
}

RadarNetworkSourceGL::Choice RadarNetworkSourceGL::choose(const std::vector<Site>& sites, double stepEpoch,
                                                          double windowMinutes) {
  const double window = windowMinutes * 60.0;
  Choice c;
  for (std::size_t i = 0; i < sites.size(); ++i) {
    const SiteVolume* best = nullptr;
    for (const SiteVolume& v : sites[i].volumes)
      if (v.epochSeconds <= stepEpoch && v.epochSeconds >= stepEpoch - window) best = &v;
    if (best) {
      c.chosen.emplace_back(i, best);
      c.estimateBytes += best->gates * kBudgetBytesPerGate;
    } else {
      c.missing.push_back(sites[i].name);
    }
  }
  return c;
}

// The steps ahead's volumes not yet in the cache, read one after another on the prefetcher's
// thread (the foreground read uses every core; the background one leaves them to the frames) and
// put under the keys load() looks for, so a step shown next reads only what this did not reach.
// A read that fails is left to the GL thread, which reads it again and says why.
class RadarNetworkSourceGL::Preparer final : public StepPreparer {
 public:
  Preparer(VolumeLayerDescription d, std::vector<Site> sites, std::vector<double> stepEpochs, double exaggeration)
      : description_(std::move(d)), sites_(std::move(sites)), stepEpochs_(std::move(stepEpochs)),
        exaggeration_(exaggeration) {}

  std::optional<Prepared> prepare(std::size_t step, const PrepareContext& context) const override {
    if (step >= stepEpochs_.size()) return std::nullopt;
    const Choice c = choose(sites_, stepEpochs_[step], description_.windowMinutes);
    if (c.chosen.empty() || c.estimateBytes > context.cache.budget()) return std::nullopt;  // load() says why
    std::uint64_t bytes = 0;
    for (const auto& [site, v] : c.chosen) {
      const std::string key = volumeKey(context.layer, v->files), parts = partsKey(context.layer, v->files);
      const bool needVolume = !context.cache.contains(key), needParts = !context.cache.contains(parts);
      if (!needVolume && !needParts) continue;
      if (!context.cache.fitsBesidesInUse(v->gates * kBudgetBytesPerGate)) break;  // the rest when shown
      if (needVolume) context.cache.markLoading(key);
      if (needParts) context.cache.markLoading(parts);
      std::shared_ptr<const volume::PolarVolume> volume = needVolume ? nullptr
                                                                     : context.cache.get<volume::PolarVolume>(key);
      volume::FieldInfo field;
      if (volume) {
        field = volume::FieldInfo{volume->fieldName, volume->fieldUnits, ""};
      } else {
        auto r = readCroppedRadar(description_, v->files);
        if (!r) {
          context.cache.abandonLoading(key);
          context.cache.abandonLoading(parts);
          continue;
        }
        field = r->volume.loadedField;
        volume = std::make_shared<const volume::PolarVolume>(std::move(*r->layout));
        bytes += volume::polarVolumeBytes(*volume);
        context.cache.put(key, volume, volume::polarVolumeBytes(*volume));  // ends the loading mark
      }
      // The parts of the upload, under a combining rule only (load() decides the rule alike).
      if (!needParts || overlapRuleOf(description_, field) == volume::OverlapRule::Integrate) {
        context.cache.abandonLoading(parts);
        continue;
      }
      auto made = RadarNetworkGL::prepareRadar(*volume, exaggeration_);
      bytes += made->bytes();
      context.cache.put(parts, made, made->bytes());
    }
    return Prepared{nullptr, bytes};
  }

 private:
  VolumeLayerDescription description_;
  std::vector<Site> sites_;
  std::vector<double> stepEpochs_;
  double exaggeration_;
};

Status RadarNetworkSourceGL::load(const VolumeLayerDescription& d, std::size_t step, SourceContext context,
                                  bool stepping) {
  // Each site's latest volume at or before the step's time, at most the window old.
  const Choice choice = choose(sites_, stepEpochs_[step], d.windowMinutes);
  const auto& chosen = choice.chosen;
  const auto& missing = choice.missing;
  const std::uint64_t estimate = choice.estimateBytes;
  if (chosen.empty())
    return makeError(d.path + ": no site has a volume within " + std::to_string(d.windowMinutes) + " minutes before " +
                     times_[step]);
  // A step must fit the budget by itself (the volumes shown cannot be dropped): refused before
  // anything is read, rather than read past the budget.
  if (estimate > context.cache.budget())
    return makeError(d.path + ": the network at " + times_[step] + " needs about " + mib(estimate) + " for its " +
                     std::to_string(chosen.size()) + " volumes, more than the memory budget of " +
                     mib(context.cache.budget()) +
                     "; raise it (--memory-budget, scene memory_budget_mb), crop the layer or shorten the window");
  const std::string gpuKey = stepKey(context.layer, step, true);
  if (auto cached = context.cache.get<StepGL>(gpuKey)) {  // shown before, still held: no read, no upload
    shown_ = std::move(cached);
  } else {
    // The volumes of the step: from the cache, else read on worker threads (the readers hold io's
    // netCDF lock around netCDF-C).
    std::map<std::string, std::shared_ptr<const volume::PolarVolume>> volumes;
    std::vector<std::string> toRead;
    for (const auto& [i, v] : chosen) {
      const std::string key = volumeKey(context.layer, v->files);
      context.cache.waitWhileLoading(key);  // the prefetcher's read in flight: wait, do not read twice
      if (auto held = context.cache.get<volume::PolarVolume>(key)) volumes[v->files] = std::move(held);
      else if (std::find(toRead.begin(), toRead.end(), v->files) == toRead.end()) toRead.push_back(v->files);
    }
    std::vector<volume::FieldInfo> fieldOf(toRead.size());
    std::vector<double> nyquistOf(toRead.size(), std::nan(""));
    std::vector<std::string> datumOf(toRead.size());
    std::string firstError;
    std::mutex mutex;
    std::vector<std::shared_ptr<const volume::PolarVolume>> layouts(toRead.size());
    std::vector<std::vector<std::string>> fieldNames(toRead.size());
    globe::parallelFor(toRead.size(), [&](std::size_t k) {
      auto r = readCroppedRadar(d, toRead[k]);
      if (!r) {
        std::lock_guard<std::mutex> lock(mutex);
        if (firstError.empty()) firstError = r.error();
        return;
      }
      layouts[k] = std::make_shared<const volume::PolarVolume>(std::move(*r->layout));
      fieldOf[k] = r->volume.loadedField;
      nyquistOf[k] = r->volume.nyquistVelocityMps;
      datumOf[k] = r->site.datumNote;
      for (const auto& f : r->volume.fields) fieldNames[k].push_back(f.name);
    });
    if (!firstError.empty()) return makeError(firstError);
    for (std::size_t k = 0; k < toRead.size(); ++k) {
      volumes[toRead[k]] = layouts[k];
      if (k == 0) {  // the field as read (the same in every file)
        field_ = fieldOf[k];
        nyquistMps_ = nyquistOf[k];
        fields_ = fieldNames[k];
        datumNote_ = datumOf[k];
      }
    }
    std::vector<std::shared_ptr<const volume::PolarVolume>> radars;
    for (const auto& [i, v] : chosen) radars.push_back(volumes.at(v->files));
    const volume::FieldKind kind = volume::classifyField(field_).kind;
    const volume::OverlapRule rule = overlapRuleOf(d, field_);
    auto built = std::make_shared<StepGL>();
    if (rule == volume::OverlapRule::Integrate) {
      // Each radar apart, as separate radar layers (with their vertical exaggeration).
      for (const auto& r : radars) {
        auto gl = RadarVolumeGL::create(*r, context.exaggeration);
        if (!gl) return makeError(r->sourcePath + ": " + gl.error());
        (*gl)->setBeamApproximation(d.beam);
        built->apart.push_back(std::move(*gl));
      }
    } else {
      // Each radar's upload parts: kept from a step that showed it (or the prefetcher's), else
      // made now on every core and kept.
      std::vector<std::shared_ptr<const NetworkRadarParts>> parts(radars.size());
      std::vector<std::size_t> toMake;
      for (std::size_t k = 0; k < radars.size(); ++k) {
        const std::string key = partsKey(context.layer, chosen[k].second->files);
        context.cache.waitWhileLoading(key);
        auto held = context.cache.get<NetworkRadarParts>(key);
        if (held && held->exaggeration == context.exaggeration) parts[k] = std::move(held);
        else toMake.push_back(k);
      }
      globe::parallelFor(toMake.size(), [&](std::size_t j) {
        parts[toMake[j]] = RadarNetworkGL::prepareRadar(*radars[toMake[j]], context.exaggeration);
      });
      for (std::size_t k : toMake)
        context.cache.put(partsKey(context.layer, chosen[k].second->files), parts[k], parts[k]->bytes());
      // A step uploads only the radars whose volume changed since the step shown before, the
      // others' tiles coming from that step's textures. A loop whose steps do not all fit the
      // budget is never replayed from the cache when played in order (least recently used goes
      // first), so its step takes those textures over; a loop that fits keeps every step for its
      // replay, so its step copies them on the GPU. Only when stepping: a reload keeps the step
      // shown until the new one is loaded (an error leaves it drawn).
      std::vector<std::shared_ptr<RadarNetworkGL>> previous;
      if (stepping && shown_ && rule_ == rule) previous = shown_->clusters;
      const bool overBudget = shown_ && static_cast<double>(times_.size()) * static_cast<double>(shown_->gpuBytes()) >
                                            static_cast<double>(context.cache.budget());
      auto gl = RadarNetworkGL::createByCluster(
          radars, rule, kind, context.exaggeration, parts, previous,
          overBudget ? RadarNetworkGL::PreviousTexture::TakeOver : RadarNetworkGL::PreviousTexture::Copy);
      if (!gl) {
        std::string why = d.path + ": " + gl.error();
        if (perRadarQuantity(kind)) why += " (leave the overlap rule out, or give integrate, to draw each radar apart)";
        return makeError(why);
      }
      built->clusters = std::move(*gl);
      // The step shown before no longer draws where its textures were taken over: out of the cache.
      if (std::any_of(previous.begin(), previous.end(), [](const auto& c) { return !c->drawable(); }))
        context.cache.erase(stepKey(context.layer, step_, true));
      // A cluster kept from the step before (the same network) uploaded nothing now.
      for (const auto& c : built->clusters)
        if (std::find(previous.begin(), previous.end(), c) == previous.end())
          radarsUploaded_ += static_cast<std::size_t>(c->radarsUploaded());
    }
    // Every volume and the step's GPU part under the budget: a volume read once serves every step
    // that shows it while it is held; the GPU part serves a loop played again.
    for (const auto& [files, v] : volumes) {
      context.cache.put(volumeKey(context.layer, files), v, volume::polarVolumeBytes(*v));
      built->read[files] = v;
    }
    // The clusters as shared parts: one kept from the step before (the same network) counts once
    // in the budget however many steps hold it.
    std::vector<volume::StepCache::SharedPart> parts;
    for (const auto& c : built->clusters) parts.push_back({c.get(), c->gpuBytes()});
    context.cache.put(gpuKey, built, built->apartBytes(), std::move(parts));
    shown_ = std::move(built);
    rule_ = rule;
  }
  // The step shown before is no longer in use: what of it no longer fits goes, released on this
  // (the GL) thread.
  // Twice: a dropped GPU step still holds its volumes until it is released.
  for (int pass = 0; pass < 2; ++pass) {
    context.cache.enforceBudget();
    context.cache.releaseDropped();
  }
  auto options = layerRenderOptions(d, field_, nyquistMps_, colourRange());
  if (!options) return options.forwardError();
  options_ = std::move(*options);
  std::vector<std::string> shown;
  std::vector<Marker> markers;
  for (const auto& [i, v] : chosen) {
    const volume::PolarVolume& r = *shown_->read.at(v->files);
    shown.push_back(sites_[i].name);
    Marker m;
    m.latDeg = r.site.latDeg;
    m.lonDeg = r.site.lonDeg;
    m.heightMeters = r.site.antennaHeightEllipsoidMeters;
    m.color = glm::vec3(1.0f);
    m.sizePx = 10.0f;
    m.label = sites_[i].name;
    markers.push_back(std::move(m));
  }
  shownSites_ = std::move(shown);
  missingSites_ = missing;
  markers_ = std::move(markers);
  synthetic_ =
      volume::fileSaysSynthetic(chosen.front().second->files.substr(0, chosen.front().second->files.find(',')));
  return Ok{};
}

std::string RadarNetworkSourceGL::title() const {
  return "network " + std::to_string(shownSites_.size()) + " radars  " + field_.name + " (" + volume::toString(rule_) +
         ")";
}

volume::ValueHistogram RadarNetworkSourceGL::histogram(int bins) const {
  // Every radar's gates over the network's value range, added bin by bin.
  const volume::ValueRange range = colourRange();
  volume::ValueHistogram out = volume::valueHistogram(std::span<const float>(), range.minValue, range.maxValue, bins);
  for (const auto& [files, radar] : shown_->read) {
    const volume::ValueHistogram h = volume::valueHistogram(radar->values, range.minValue, range.maxValue, bins);
    for (std::size_t b = 0; b < out.counts.size() && b < h.counts.size(); ++b) out.counts[b] += h.counts[b];
    out.below += h.below;
    out.above += h.above;
    out.noEcho += h.noEcho;
    out.noData += h.noData;
  }
  return out;
}

Status RadarNetworkSourceGL::showStep(std::size_t step, double /*fraction*/, SourceContext context) {
  if (step >= stepEpochs_.size()) return makeError(description_.path + ": no network step " + std::to_string(step));
  if (step == step_) return Ok{};
  if (auto st = load(description_, step, context, true); !st) return st;
  step_ = step;
  return Ok{};
}

std::unique_ptr<StepPreparer> RadarNetworkSourceGL::preparer(double exaggeration) const {
  return std::make_unique<Preparer>(description_, sites_, stepEpochs_, exaggeration);
}

Status RadarNetworkSourceGL::setDescription(const VolumeLayerDescription& d, SourceContext context) {
  switch (layerChange(description_, d)) {
    case LayerChange::None: return Ok{};
    case LayerChange::Reload: {
      if (d.path != description_.path)
        return makeError(d.path + ": a network layer's files cannot be changed in place");
      // Another field, crop, datum, rule or window: every site read again. The step shown stays
      // until the new one is loaded (an error leaves it drawn).
      auto keep = shown_;
      context.cache.erasePrefix(stepKeyPrefix(context.layer));
      if (auto st = load(d, step_, context); !st) {
        shown_ = std::move(keep);
        return st;
      }
      description_ = d;
      return Ok{};
    }
    case LayerChange::Options: break;
  }
  auto options = layerRenderOptions(d, field_, nyquistMps_, colourRange());
  if (!options) return options.forwardError();
  options_ = std::move(*options);
  description_ = d;
  return Ok{};
}

Status RadarNetworkSourceGL::applyExaggeration(SourceContext context) {
  auto keep = shown_;
  context.cache.erasePrefix(stepKeyPrefix(context.layer));  // steps uploaded at the old exaggeration
  if (auto st = load(description_, step_, context); !st) {
    shown_ = std::move(keep);
    return st;
  }
  return Ok{};
}

bool RadarNetworkSourceGL::valuesCombine() const { return !perRadarQuantity(volume::classifyField(field_).kind); }

const VolumeGL& RadarNetworkSourceGL::volume() const {
  if (!shown_->clusters.empty()) return *shown_->clusters.front();
  return *shown_->apart.front();
}

LegendPart RadarNetworkSourceGL::legendPart() const {
  std::string subtitle = std::to_string(shownSites_.size()) + " radars, latest volumes at " + utcLabel(times_[step_]);
  if (rule_ != volume::OverlapRule::Integrate)
    subtitle += " (" + std::string(volume::toString(rule_)) + " where they overlap)";
  else if (perRadarQuantity(volume::classifyField(field_).kind))
    subtitle += " (each radar apart: values of different sites are not combined)";
  else subtitle += " (each radar apart, integrated where they overlap)";
  if (!missingSites_.empty()) subtitle += "; " + std::to_string(missingSites_.size()) + " sites missing";
  // The far field (FarFieldGL.h) draws DVR from slabs where every pixel is 2 km or wider.
  if (options_.farField == FarField::Auto && options_.render.mode == volume::VolumeRenderMode::Dvr)
    subtitle += "; from afar drawn from vertical slabs";
  const std::string name = "network " + field_.name;
  return LegendPart{name, subtitle, LegendKey{name, field_.units, options_.render.transfer.colors}, synthetic_};
}

LayerMemory RadarNetworkSourceGL::memory() const {
  std::uint64_t cpu = 0;
  for (const auto& [files, v] : shown_->read) cpu += v->byteSize();
  std::uint64_t gpu = 0;
  for (const auto& c : shown_->clusters) gpu += c->gpuBytes();
  for (const auto& r : shown_->apart) {
    gpu += r->gpuBytes();
    cpu += volume::polarVolumeBytes(r->polar());
  }
  return LayerMemory{title(), cpu, gpu};
}

std::optional<std::string> RadarNetworkSourceGL::readoutAt(const glm::dvec3& eye, const glm::dvec3& dir,
                                                           double tMaxMeters, double stepMeters) const {
  std::optional<RayValue> best;
  if (!shown_->apart.empty()) {
    // Each radar apart: the nearest first echo of any radar, read as stored (as a radar layer's
    // readout), named by its site; other radars' values there are their own (not combined).
    std::size_t which = 0;
    for (std::size_t i = 0; i < shown_->apart.size(); ++i) {
      const auto hit = firstValueAlong(shown_->apart[i]->referenceSampler(), eye, dir, tMaxMeters, stepMeters,
                                       volume::Interpolation::Nearest);
      if (hit && (!best || hit->tMeters < best->tMeters)) {
        best = hit;
        which = i;
      }
    }
    if (!best) return std::nullopt;
    globe::Geodetic g = globe::ecefToGeodetic(best->ecef);
    g.heightMeters /= shown_->apart[which]->exaggeration();
    char text[320];
    std::snprintf(text, sizeof text, "%.1f %s  (radar %s, each radar apart; height %.0f m above sea level)",
                  best->value, field_.units.c_str(), markers_[which].label.c_str(), seaLevelHeightMeters(g));
    return "network " + field_.name + ": " + text;
  }
  // The nearest first value over the clusters (apart: at most one holds a point).
  // Along the ray as drawn (exaggerated or not); the point then at its true height.
  const RadarNetworkGL* where = nullptr;
  for (const auto& c : shown_->clusters) {
    const auto hit =
        firstValueAlong(c->referenceSampler(), eye, dir, tMaxMeters, stepMeters, volume::Interpolation::Linear);
    if (hit && (!best || hit->tMeters < best->tMeters)) {
      best = hit;
      where = c.get();
    }
  }
  if (!best) return std::nullopt;
  globe::Geodetic g = globe::ecefToGeodetic(best->ecef);
  g.heightMeters /= where->exaggeration();
  const glm::dvec3 trueEcef = globe::geodeticToEcef(g);
  const auto lead = where->network().leadingRadar(trueEcef, volume::Interpolation::Linear);
  const auto [first, last] = where->network().coverage().radarsAt(trueEcef);
  std::string leader;
  if (lead) {
    // The leading radar's site as the legend names it: the shown site at its position.
    const volume::PolarVolume& r = where->network().radar(*lead);
    for (std::size_t i = 0; i < markers_.size(); ++i)
      if (std::abs(markers_[i].latDeg - r.site.latDeg) < 1e-9 && std::abs(markers_[i].lonDeg - r.site.lonDeg) < 1e-9)
        leader = ", led by " + markers_[i].label;
  }
  char text[320];
  std::snprintf(text, sizeof text, "%.1f %s  (%s of %d radars over the point%s; height %.0f m above sea level)",
                best->value, field_.units.c_str(), volume::toString(rule_), static_cast<int>(last - first),
                leader.c_str(), seaLevelHeightMeters(g));
  return "network " + field_.name + ": " + text;
}

std::vector<const VolumeGL*> RadarNetworkSourceGL::volumes() const {
  std::vector<const VolumeGL*> out;
  for (const auto& c : shown_->clusters) out.push_back(c.get());
  for (const auto& r : shown_->apart) out.push_back(r.get());
  return out;
}

volume::ValueRange RadarNetworkSourceGL::colourRange() const {
  // The values of every volume shown.
  volume::ValueRange range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const auto& [files, v] : shown_->read) {
    range.minValue = std::min(range.minValue, static_cast<double>(v->minValue));
    range.maxValue = std::max(range.maxValue, static_cast<double>(v->maxValue));
  }
  return range;
}

std::string RadarNetworkSourceGL::loadNote() const {
  std::string note = description_.path + ": network of " + std::to_string(sites_.size()) + " sites, " +
                     std::to_string(times_.size()) + " times; at " + times_[step_] + " " +
                     std::to_string(shownSites_.size()) + " shown" +
                     (rule_ == volume::OverlapRule::Integrate
                          ? std::string(" each apart (integrate")
                          : " as one volume (" + std::string(volume::toString(rule_)) + " where they overlap") +
                     (!valuesCombine() ? ": values of different sites are not combined)" : ")");
  if (!missingSites_.empty()) {
    note += ", no volume within " + std::to_string(static_cast<int>(description_.windowMinutes)) + " min: ";
    for (std::size_t i = 0; i < missingSites_.size(); ++i) note += (i ? ", " : "") + missingSites_[i];
  }
  return note + "; " + datumNote_;
}

}  // namespace atmoglobe::engine
