#pragma once
// A radar volume layer (VolumeSourceGL.h): one volume, or a loop (a directory, glob or list
// holding several times of one site) whose volumes are the layer's time steps. The site's marker
// and range rings go with it; the cursor readout reads gates as stored (nearest neighbour), so a
// readout is a row of `atmoglobe gates`.
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeSourceGL.h>
#include <atmoglobe/volume/RadarLoad.h>

#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::engine {

struct RadarShown;

/// A radar loop's volume as the renderer draws it, CPU side only: read (`files`: one loop step),
/// cropped; its time and datum note.
struct RadarStepData {
  volume::PolarVolume layout;  ///< empty once `prepared` holds it
  std::string timeIso8601, datumNote;
  /// Ready for upload (RadarVolumeGL::prepare at the scene's exaggeration), made by the
  /// background loader; null: upload from `layout`.
  std::shared_ptr<const RadarVolumeGL::Prepared> prepared;
};
/// One radar volume (a file, or a set's files as one comma list) read with its render layout and
/// cut to the layer's crop box: what a radar layer's open, reload and loop steps, and a network's
/// sites, load. Thread-safe.
Result<volume::LoadedRadar> readCroppedRadar(const VolumeLayerDescription& description, const std::string& files);
/// Reads one loop step (`files`: a file, or a set's files as one comma list) for `description`.
/// Thread-safe (the readers hold io's netCDF lock while they call netCDF-C).
Result<RadarStepData> prepareRadarStep(const VolumeLayerDescription& description, const std::string& files);

class RadarSourceGL final : public VolumeSourceGL {
 public:
  /// Reads the radar `description` names (a loop: its latest volume shown).
  static Result<std::unique_ptr<RadarSourceGL>> open(const VolumeLayerDescription& description, SourceContext context);
  /// A source around a volume already uploaded (tests, benchmarks): no file behind it, no loop.
  static std::unique_ptr<RadarSourceGL> fromVolume(std::shared_ptr<RadarVolumeGL> volume,
                                                   const VolumeRenderOptions& options, const Marker& siteMarker);

  const VolumeGL& volume() const override { return *volume_; }
  const RadarVolumeGL& radarVolume() const { return *volume_; }
  std::string title() const override;
  std::vector<std::string> fieldChoices() const override { return fields_; }
  std::string fieldShown() const override { return volume_->polar().fieldName; }
  volume::ValueRange colourRange() const override;
  volume::ValueHistogram histogram(int bins) const override;

  Result<std::vector<std::string>> times() const override { return loopTimes_; }
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
  const Marker* siteMarker() const override { return &siteMarker_; }
  std::vector<map::GeoPolyline> rangeRings() const override;
  std::string loadNote() const override { return description_.path + ": " + datumNote_; }

  /// The site's name as the file gives it; the volume start shown.
  const std::string& siteName() const { return siteName_; }
  const std::string& timeIso8601() const { return timeIso8601_; }
  /// A loop's files per step (a comma list read as one volume), oldest first; empty for one volume.
  const std::vector<std::string>& loopFiles() const { return loopFiles_; }
  /// The field read (name, units, standard name) the colours were made for.
  const volume::FieldInfo& loadedField() const { return loadedField_; }

 private:
  RadarSourceGL() = default;
  Status reload(const VolumeLayerDescription& description, SourceContext context);
  void cacheShown(volume::StepCache& cache, const std::string& key);
  /// Takes a volume read and uploaded (open, reload): the volume, options, time, field, datum.
  void show(RadarShown loaded);
  std::shared_ptr<RadarVolumeGL> volume_;  ///< shared with the step cache (memory budget)
  Marker siteMarker_;
  std::string datumNote_;    ///< which vertical datum / geoid undulation was used
  std::string siteName_;     ///< as the file names it
  std::string timeIso8601_;  ///< volume start
  bool synthetic_ = false;   ///< the file says SYNTHETIC
  std::vector<std::string> loopFiles_, loopTimes_;
  std::size_t step_ = 0;
  std::vector<std::string> fields_;  ///< the fields the file holds
  volume::FieldInfo loadedField_;
  double nyquistMps_ = 0.0;  ///< the velocity scale the colours were made with
};

}  // namespace atmoglobe::engine
