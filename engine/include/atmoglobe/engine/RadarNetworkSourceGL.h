#pragma once
// A radar network layer (VolumeSourceGL.h): a set of files (a directory, glob or comma list) holding
// several sites and times. Its times are the volume times of the set (times within a minute are
// one step); at each, every site shows its latest volume at most windowMinutes old, and the sites
// with none are named in the load note and the legend. A site marker per radar shown.
//
// Drawn one of two ways (docs/networks.md):
// - one volume per cluster of overlapping radars (RadarNetworkGL.h) under the mean, lowest-beam or
//   maximum rule: one value where radars overlap;
// - each radar apart (RadarVolumeGL.h), integrated where they overlap as separate radar layers
//   are: the "integrate" rule, and the default for velocity and differential phase, whose values
//   from different sites cannot be combined (a radial velocity is along its own radar's beam).
//
// Memory (docs/memory.md): every volume read is an entry of the scene's step cache, and so is each
// step's GPU network; a step whose volumes alone would exceed the budget is refused before any is
// read, and volumes of other steps are dropped least recently used first.
#include <atmoglobe/engine/RadarNetworkGL.h>
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeSourceGL.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace atmoglobe::engine {

class RadarNetworkSourceGL final : public VolumeSourceGL {
 public:
  /// The network `description` names, showing its latest time, when its path is a set of files
  /// holding several radar sites (every file's metadata read once); null for one file or one
  /// site's volumes. Errors: the readers', a vertical exaggeration other than 1 under a rule that
  /// combines radars (not drawn yet), the overlap rule's, a step larger than the memory budget.
  static Result<std::unique_ptr<RadarNetworkSourceGL>> openIfNetwork(const VolumeLayerDescription& description,
                                                                     SourceContext context);

  /// The largest cluster of the network, or the first radar when each is drawn apart (volumes()
  /// has every cluster or radar: RadarNetworkGL::createByCluster).
  const VolumeGL& volume() const override;
  std::vector<const VolumeGL*> volumes() const override;
  /// The clusters (empty when each radar is drawn apart), the radars drawn apart (else empty).
  const std::vector<std::shared_ptr<RadarNetworkGL>>& clusters() const { return shown_->clusters; }
  const std::vector<std::shared_ptr<RadarVolumeGL>>& radarsApart() const { return shown_->apart; }
  /// The rule in effect: the layer's, else mean (integrate for velocity and differential phase).
  volume::OverlapRule rule() const { return rule_; }
  /// Whether values of different sites can be combined (not velocity or differential phase).
  bool valuesCombine() const;
  std::string title() const override;
  std::vector<std::string> fieldChoices() const override { return fields_; }
  std::string fieldShown() const override { return field_.name; }
  volume::ValueRange colourRange() const override;
  volume::ValueHistogram histogram(int bins) const override;

  Result<std::vector<std::string>> times() const override { return times_; }
  TimeMatching timeMatching() const override { return TimeMatching::LatestAtOrBefore; }
  bool interpolatesInTime() const override { return false; }
  std::size_t step() const override { return step_; }
  Status showStep(std::size_t step, double fraction, SourceContext context) override;
  std::unique_ptr<StepPreparer> preparer(double exaggeration) const override;

  Status setDescription(const VolumeLayerDescription& description, SourceContext context) override;
  Status applyExaggeration(SourceContext context) override;

  LegendPart legendPart() const override;
  LayerMemory memory() const override;
  std::optional<std::string> readoutAt(const glm::dvec3& eyeEcef, const glm::dvec3& dir, double tMaxMeters,
                                       double stepMeters) const override;
  std::vector<Marker> siteMarkers() const override { return markers_; }
  std::string loadNote() const override;

  /// The sites shown at the current step, and those with no volume within the window there.
  const std::vector<std::string>& sitesShown() const { return shownSites_; }
  const std::vector<std::string>& sitesMissing() const { return missingSites_; }
  /// Radars whose values were uploaded since the layer was opened (a step that takes over the
  /// previous step's textures uploads only the radars whose volume changed).
  std::size_t radarsUploaded() const { return radarsUploaded_; }

 private:
  RadarNetworkSourceGL() = default;
  struct SiteVolume {
    std::string files;  ///< one volume's files as a comma list
    std::string timeIso8601;
    double epochSeconds = 0.0;
    std::uint64_t gates = 0;  ///< of the field, from the metadata: what reading it will cost
  };
  struct Site {
    std::string name;
    double latDeg = 0.0, lonDeg = 0.0;
    std::vector<SiteVolume> volumes;  ///< oldest first
  };
  /// A step on the GPU: the clusters or the radars apart, and the volumes they hold by files.
  struct StepGL {
    std::vector<std::shared_ptr<RadarNetworkGL>> clusters;
    std::vector<std::shared_ptr<RadarVolumeGL>> apart;
    std::map<std::string, std::shared_ptr<const volume::PolarVolume>> read;
    std::uint64_t gpuBytes() const;    ///< the clusters' and apartBytes()
    std::uint64_t apartBytes() const;  ///< the volumes drawn apart, with their CPU copies
  };
  /// The volumes a step shows: each site's latest at or before its time, at most the window old.
  struct Choice {
    std::vector<std::pair<std::size_t, const SiteVolume*>> chosen;  ///< (site, volume)
    std::vector<std::string> missing;                               ///< sites with none
    std::uint64_t estimateBytes = 0;                                ///< of reading them all (metadata)
  };
  static Choice choose(const std::vector<Site>& sites, double stepEpoch, double windowMinutes);
  /// Reads the volumes of steps ahead into the cache on ScenePrefetcher's thread.
  class Preparer;
  /// Reads the sites' volumes for `step` not in the cache (on worker threads), uploads the network,
  /// colours it.
  /// `stepping`: showStep's load, which may take over the textures of the step shown before.
  Status load(const VolumeLayerDescription& description, std::size_t step, SourceContext context,
              bool stepping = false);

  std::vector<Site> sites_;
  std::vector<std::string> times_;
  std::vector<double> stepEpochs_;
  std::size_t step_ = 0;
  std::shared_ptr<const StepGL> shown_;  ///< also a step cache entry (in use while shown)
  volume::OverlapRule rule_ = volume::OverlapRule::WeightedMean;
  std::vector<std::string> shownSites_, missingSites_;
  std::vector<Marker> markers_;
  std::vector<std::string> fields_;
  volume::FieldInfo field_;
  double nyquistMps_ = 0.0;
  bool synthetic_ = false;
  std::size_t radarsUploaded_ = 0;
  std::string datumNote_;
};

}  // namespace atmoglobe::engine
