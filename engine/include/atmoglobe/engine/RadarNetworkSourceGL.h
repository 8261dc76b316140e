#pragma once
// A radar network layer (VolumeSourceGL.h): a set of files (a directory, glob or comma list) holding
// several sites and times, drawn as one volume (RadarNetworkGL.h) under the layer's overlap rule.
// Its times are the volume times of the set (times within a minute are one step); at each, every
// site shows its latest volume at most windowMinutes old, and the sites with none are named in
// the load note and the legend. A site marker per radar shown.
#include <atmoglobe/engine/RadarNetworkGL.h>
#include <atmoglobe/engine/VolumeSourceGL.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::engine {

class RadarNetworkSourceGL final : public VolumeSourceGL {
 public:
  /// The network `description` names, showing its latest time, when its path is a set of files
  /// holding several radar sites (every file's metadata read once); null for one file or one
  /// site's volumes. Errors: the readers', a vertical exaggeration other than 1 (not drawn for
  /// networks yet), the overlap rule's.
  static Result<std::unique_ptr<RadarNetworkSourceGL>> openIfNetwork(const VolumeLayerDescription& description,
                                                                     SourceContext context);

  /// The largest cluster of the network (volumes() has every cluster: radars whose clip spheres
  /// meet, RadarNetworkGL::createByCluster).
  const VolumeGL& volume() const override { return *clusters_.front(); }
  std::vector<const VolumeGL*> volumes() const override;
  const std::vector<std::shared_ptr<RadarNetworkGL>>& clusters() const { return clusters_; }
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

 private:
  RadarNetworkSourceGL() = default;
  struct SiteVolume {
    std::string files;  ///< one volume's files as a comma list
    std::string timeIso8601;
    double epochSeconds = 0.0;
  };
  struct Site {
    std::string name;
    double latDeg = 0.0, lonDeg = 0.0;
    std::vector<SiteVolume> volumes;  ///< oldest first
  };
  /// Reads the sites' volumes for `step` (on worker threads), uploads the network, colours it.
  Status load(const VolumeLayerDescription& description, std::size_t step, double exaggeration);

  std::vector<Site> sites_;
  std::vector<std::string> times_;
  std::vector<double> stepEpochs_;
  std::size_t step_ = 0;
  std::vector<std::shared_ptr<RadarNetworkGL>> clusters_;
  volume::OverlapRule rule_ = volume::OverlapRule::WeightedMean;
  /// The volumes read, by their files (kept while a step shows them, so a step that changes
  /// a few sites reads only those).
  std::map<std::string, std::shared_ptr<const volume::PolarVolume>> read_;
  std::vector<std::string> shownSites_, missingSites_;
  std::vector<Marker> markers_;
  std::vector<std::string> fields_;
  volume::FieldInfo field_;
  double nyquistMps_ = 0.0;
  bool synthetic_ = false;
  std::string datumNote_;
};

}  // namespace atmoglobe::engine
