#include <atmoglobe/engine/RadarNetworkSourceGL.h>

#include <atmoglobe/engine/RadarSourceGL.h>
#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/RadarVolumeSet.h>
#include <atmoglobe/volume/SliceSource.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <span>
#include <thread>

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

// No steps prepared ahead (the network reads its sites on worker threads itself).
class NoPreparer final : public StepPreparer {
 public:
  std::optional<Prepared> prepare(std::size_t) const override { return std::nullopt; }
};

// The values of every cluster.
volume::ValueRange unionRange(const std::vector<std::shared_ptr<RadarNetworkGL>>& clusters) {
  volume::ValueRange range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const auto& c : clusters) {
    range.minValue = std::min(range.minValue, c->valueRange().minValue);
    range.maxValue = std::max(range.maxValue, c->valueRange().maxValue);
  }
  return range;
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
  if (auto st = s->load(d, s->stepEpochs_.size() - 1, context.exaggeration); !st) return st.forwardError();
  s->step_ = s->stepEpochs_.size() - 1;
  return s;
}

Status RadarNetworkSourceGL::load(const VolumeLayerDescription& d, std::size_t step, double exaggeration) {
  if (exaggeration != 1.0)
    return makeError(d.path + ": a radar network is drawn at true scale only (no vertical exaggeration yet)");
  const double t = stepEpochs_[step], window = d.windowMinutes * 60.0;
  // Each site's latest volume at or before the step's time, at most the window old.
  std::vector<std::pair<std::size_t, const SiteVolume*>> chosen;
  std::vector<std::string> missing;
  for (std::size_t i = 0; i < sites_.size(); ++i) {
    const SiteVolume* best = nullptr;
    for (const SiteVolume& v : sites_[i].volumes)
      if (v.epochSeconds <= t && v.epochSeconds >= t - window) best = &v;
    if (best) chosen.emplace_back(i, best);
    else missing.push_back(sites_[i].name);
  }
  if (chosen.empty())
    return makeError(d.path + ": no site has a volume within " + std::to_string(d.windowMinutes) + " minutes before " +
                     times_[step]);
  // Read what is not read yet, on worker threads (the readers hold io's netCDF lock around netCDF-C).
  std::vector<std::string> toRead;
  for (const auto& [i, v] : chosen)
    if (!read_.count(v->files)) toRead.push_back(v->files);
  std::map<std::string, std::shared_ptr<const volume::PolarVolume>> fresh;
  std::vector<volume::FieldInfo> fieldOf(toRead.size());
  std::vector<double> nyquistOf(toRead.size(), std::nan(""));
  std::vector<std::string> datumOf(toRead.size());
  std::string firstError;
  std::mutex mutex;
  std::atomic<std::size_t> next{0};
  std::vector<std::shared_ptr<const volume::PolarVolume>> layouts(toRead.size());
  std::vector<std::vector<std::string>> fieldNames(toRead.size());
  auto work = [&] {
    for (std::size_t k = next++; k < toRead.size(); k = next++) {
      auto r = readCroppedRadar(d, toRead[k]);
      if (!r) {
        std::lock_guard<std::mutex> lock(mutex);
        if (firstError.empty()) firstError = r.error();
        continue;
      }
      layouts[k] = std::make_shared<const volume::PolarVolume>(std::move(*r->layout));
      fieldOf[k] = r->volume.loadedField;
      nyquistOf[k] = r->volume.nyquistVelocityMps;
      datumOf[k] = r->site.datumNote;
      for (const auto& f : r->volume.fields) fieldNames[k].push_back(f.name);
    }
  };
  const unsigned threads =
      std::max(1u, std::min<unsigned>(std::thread::hardware_concurrency(), static_cast<unsigned>(toRead.size())));
  std::vector<std::thread> pool;
  for (unsigned w = 1; w < threads; ++w) pool.emplace_back(work);
  work();
  for (auto& th : pool) th.join();
  if (!firstError.empty()) return makeError(firstError);
  for (std::size_t k = 0; k < toRead.size(); ++k) {
    fresh[toRead[k]] = layouts[k];
    if (k == 0) {  // the field as read (the same in every file; the kinds are checked by the network)
      field_ = fieldOf[k];
      nyquistMps_ = nyquistOf[k];
      fields_ = fieldNames[k];
      datumNote_ = datumOf[k];
    }
  }
  for (auto& [files, v] : read_)
    if (!fresh.count(files)) fresh[files] = v;
  std::vector<std::shared_ptr<const volume::PolarVolume>> radars;
  std::vector<std::string> shown;
  std::vector<Marker> markers;
  for (const auto& [i, v] : chosen) {
    radars.push_back(fresh.at(v->files));
    shown.push_back(sites_[i].name);
    Marker m;
    m.latDeg = radars.back()->site.latDeg;
    m.lonDeg = radars.back()->site.lonDeg;
    m.heightMeters = radars.back()->site.antennaHeightEllipsoidMeters;
    m.color = glm::vec3(1.0f);
    m.sizePx = 10.0f;
    m.label = sites_[i].name;
    markers.push_back(std::move(m));
  }
  const volume::FieldKind kind = volume::classifyField(field_).kind;
  const volume::OverlapRule rule = d.overlap.value_or(volume::OverlapRule::WeightedMean);
  auto gl = RadarNetworkGL::createByCluster(radars, rule, kind);
  if (!gl) return makeError(d.path + ": " + gl.error());
  std::vector<std::shared_ptr<RadarNetworkGL>> clusters(std::make_move_iterator(gl->begin()),
                                                        std::make_move_iterator(gl->end()));
  auto options = layerRenderOptions(d, field_, nyquistMps_, unionRange(clusters));
  if (!options) return options.forwardError();
  clusters_ = std::move(clusters);
  rule_ = rule;
  options_ = std::move(*options);
  read_.clear();
  for (const auto& [i, v] : chosen) read_[v->files] = fresh.at(v->files);
  shownSites_ = std::move(shown);
  missingSites_ = std::move(missing);
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
  for (const auto& [files, radar] : read_) {
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
  if (auto st = load(description_, step, context.exaggeration); !st) return st;
  step_ = step;
  return Ok{};
}

std::unique_ptr<StepPreparer> RadarNetworkSourceGL::preparer(double) const { return std::make_unique<NoPreparer>(); }

Status RadarNetworkSourceGL::setDescription(const VolumeLayerDescription& d, SourceContext context) {
  switch (layerChange(description_, d)) {
    case LayerChange::None: return Ok{};
    case LayerChange::Reload: {
      if (d.path != description_.path)
        return makeError(d.path + ": a network layer's files cannot be changed in place");
      read_.clear();  // another field, crop, datum, rule or window: every site read again
      if (auto st = load(d, step_, context.exaggeration); !st) return st;
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
  return load(description_, step_, context.exaggeration);
}

LegendPart RadarNetworkSourceGL::legendPart() const {
  std::string subtitle = std::to_string(shownSites_.size()) + " radars, latest volumes at " + utcLabel(times_[step_]) +
                         " (" + volume::toString(rule_) + " where they overlap)";
  if (!missingSites_.empty()) subtitle += "; " + std::to_string(missingSites_.size()) + " sites missing";
  const std::string name = "network " + field_.name;
  return LegendPart{name, subtitle, LegendKey{name, field_.units, options_.render.transfer.colors}, synthetic_};
}

LayerMemory RadarNetworkSourceGL::memory() const {
  std::uint64_t cpu = 0;
  for (const auto& [files, v] : read_) cpu += v->byteSize();
  std::uint64_t gpu = 0;
  for (const auto& c : clusters_) gpu += c->gpuBytes();
  return LayerMemory{title(), cpu, gpu};
}

std::optional<std::string> RadarNetworkSourceGL::readoutAt(const glm::dvec3& eye, const glm::dvec3& dir,
                                                           double tMaxMeters, double stepMeters) const {
  // The nearest first value over the clusters (apart: at most one holds a point).
  std::optional<RayValue> best;
  const volume::RadarNetworkSampler* where = nullptr;
  for (const auto& c : clusters_) {
    const auto hit = firstValueAlong(c->network(), eye, dir, tMaxMeters, stepMeters, volume::Interpolation::Linear);
    if (hit && (!best || hit->tMeters < best->tMeters)) {
      best = hit;
      where = &c->network();
    }
  }
  if (!best) return std::nullopt;
  const auto lead = where->leadingRadar(best->ecef, volume::Interpolation::Linear);
  const auto [first, last] = where->coverage().radarsAt(best->ecef);
  const globe::Geodetic g = globe::ecefToGeodetic(best->ecef);
  std::string leader;
  if (lead) {
    // The leading radar's site as the legend names it: the shown site at its position.
    const volume::PolarVolume& r = where->radar(*lead);
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
  for (const auto& c : clusters_) out.push_back(c.get());
  return out;
}

volume::ValueRange RadarNetworkSourceGL::colourRange() const { return unionRange(clusters_); }

std::string RadarNetworkSourceGL::loadNote() const {
  std::string note = description_.path + ": network of " + std::to_string(sites_.size()) + " sites, " +
                     std::to_string(times_.size()) + " times; at " + times_[step_] + " " +
                     std::to_string(shownSites_.size()) + " shown";
  if (!missingSites_.empty()) {
    note += ", no volume within " + std::to_string(static_cast<int>(description_.windowMinutes)) + " min: ";
    for (std::size_t i = 0; i < missingSites_.size(); ++i) note += (i ? ", " : "") + missingSites_[i];
  }
  return note + "; " + datumNote_;
}

}  // namespace atmoglobe::engine
