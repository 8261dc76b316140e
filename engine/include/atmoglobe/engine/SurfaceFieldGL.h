#pragma once
// A 2-D field draped on the globe (SurfaceLayer.h): the fill, in the grid's own geometry (a mesh
// of its grid points on the WGS84 ellipsoid, the values bilinear at each fragment's fractional
// column and row as volume::SurfaceSampler takes them), and contour lines (GDAL's generator in
// the grid's index space, map::contourLinesOnGrid) drawn as map lines, labelled with their values.
//
// Drawn after the globe, before the map lines and the volumes, with the depth test on and no
// depth writes: lifted toward the eye and cut at the horizon as map lines are (MapRendererGL.h),
// so the volumes' march still stops at the globe and composites over the field. Missing values
// and values below the colour table's first stop are not drawn.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Legend.h>
#include <atmoglobe/engine/MapRendererGL.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/engine/SurfaceLayer.h>
#include <atmoglobe/map/Contours.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/SurfaceField.h>

#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::engine {

class SurfaceFieldGL {
 public:
  /// Uploads the field and finds its contour lines. Errors: the colour table's, GDAL's, a field
  /// too large for one texture.
  static Result<std::unique_ptr<SurfaceFieldGL>> create(SurfaceData data, const SurfaceLayerDescription& description);
  ~SurfaceFieldGL();
  SurfaceFieldGL(const SurfaceFieldGL&) = delete;
  SurfaceFieldGL& operator=(const SurfaceFieldGL&) = delete;

  /// The fill (when the description asks for it), into the bound framebuffer.
  void drawFill(const Camera& camera);
  /// The contour lines and the wind barbs. Barbs sit at grid points about kBarbSpacingPx apart
  /// on the screen (every k-th row and column, k from the pixel footprint at the view's centre),
  /// each kBarbLengthPx long there; they are built again when the view's scale or place changes.
  void drawContours(const Camera& camera);
  static constexpr double kBarbSpacingPx = 42.0, kBarbLengthPx = 26.0;
  /// The contour lines' labels (each line's value every 1200 km along it, or at its middle when
  /// shorter) as markers without a sprite, for the scene's label placement (which drops those that
  /// would overlap).
  const std::vector<Marker>& contourLabels() const { return labels_; }
  const std::vector<map::ContourLine>& contours() const { return contours_; }
  /// Title, subtitle (what, when, which levels) and the fill's colour key (none without a fill).
  std::string title() const;
  std::string subtitle() const;
  std::optional<LegendKey> key() const;

  const volume::SurfaceField& field() const { return field_; }
  const volume::SurfaceSampler& sampler() const { return *sampler_; }
  const SurfaceLayerDescription& description() const { return description_; }
  /// What it was made from, for drawing it again under another description of the same data
  /// (sameSurfaceData) without reading the file again.
  SurfaceData data() const;
  /// An ensemble statistic's members and each one's value at a point (the field's horizontal
  /// interpolation; NaN outside or missing); empty without a statistic.
  std::vector<std::pair<long, double>> memberValuesAt(double latDeg, double lonDeg) const;
  /// Drawn (fill, contours, labels, barbs, legend); the viewer's panel switches it.
  bool visible = true;
  /// The fill's colours (the description's table over its range, else the field's values).
  const volume::ColorTable& table() const { return table_; }

 private:
  SurfaceFieldGL() = default;
  volume::SurfaceField field_;
  std::unique_ptr<volume::SurfaceSampler> sampler_;
  SurfaceLayerDescription description_;
  volume::ColorTable table_;
  ShaderProgramGL program_;
  unsigned int vao_ = 0, vbo_ = 0, ibo_ = 0, values_ = 0, tableTexture_ = 0;
  int indexCount_ = 0;
  glm::dvec3 originEcef_{0.0};
  double tableLo_ = 0.0, tableHi_ = 1.0;
  std::unique_ptr<MapRendererGL> lines_;
  std::vector<map::ContourLine> contours_;
  std::vector<Marker> labels_;
  // Wind barbs.
  std::optional<volume::GridVolume> windGrid_;
  volume::WindComponents wind_;
  std::string windNote_;
  std::unique_ptr<MapRendererGL> barbs_;
  // An ensemble statistic's members (SurfaceData::members) and their samplers.
  std::vector<std::pair<long, volume::SurfaceField>> members_;
  std::vector<std::unique_ptr<volume::SurfaceSampler>> memberSamplers_;
  std::vector<double> barbKey_;
  void buildBarbs(const Camera& camera);
};

}  // namespace atmoglobe::engine
