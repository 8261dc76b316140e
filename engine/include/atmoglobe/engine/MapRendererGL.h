#pragma once
// Map context on the globe: GSHHG coastlines and WDBII country and state/province borders (Debian
// gmt-gshhg, map/Gshhg.h), user vector files (map/VectorFile.h) and range rings, as lines on the
// ellipsoid.
//
// - Level of detail by distance (map/MapLod.h): each bin in view at the coarsest GSHHG level
//   whose point spacing is at most two pixels at its nearest point (bins nest: a bin is drawn
//   whole or handed to the finer bins inside it), so an oblique view is fine near the eye and
//   coarse toward the horizon; only the bins in view are read (a bin is dropped when its
//   bounding sphere is outside the frustum or all its samples are behind the horizon) and built
//   (densified along the geodesic to the level's segment length), then kept in a cache. State
//   and province borders are left out at the crude level (whole-hemisphere views).
// - Precision: each chunk (a GSHHG bin, or a piece of a user line) is float32 (hi, lo) pairs
//   relative to a double origin; the shader subtracts the eye's (hi, lo), so points are placed
//   relative to the eye to sub-millimetre precision from 1 m to 1e7 m.
// - Occlusion, no z-fighting: drawn after the globe with the depth test on and depth writes off,
//   each line's depth pulled toward the eye by a relative lift (kDepthLift: 1 %, far above the
//   chord sag of the lines and the float rounding of the globe), and the far side of the Earth
//   cut analytically per fragment ((V - P) . P > 0 in scaled space), so the lift never lets a
//   line show through the Earth; tests count the pixels (MapRender tests).
// - Width in pixels (screen-space quads, antialiased edges) and colour per layer.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/Scene.h>
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/map/GeoLines.h>
#include <atmoglobe/map/Gshhg.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::engine {

/// The relative depth lift of map lines (see above).
inline constexpr float kMapDepthLift = 0.01f;

/// The uniforms of the precision scheme above for geometry relative to `originEcef` (map lines,
/// draped fields): u_eyeHi and u_eyeLo (the eye's offset from the origin split into a float and
/// its remainder), u_invRadii (1/a, 1/a, 1/b) and u_originScaled (the origin times it) for the
/// horizon test, on the program in use.
void setEyeRelativeUniformsGL(const ShaderProgramGL& program, const glm::dvec3& eyeEcef, const glm::dvec3& originEcef);

/// The state of what is drawn over the globe without hiding the volumes (map lines, draped
/// fields): reverse-Z depth test on, depth writes off, straight-alpha blending; and back.
void beginOverGlobeGL();
void endOverGlobeGL();

struct MapLineStyle {
  glm::vec3 color{1.0f};
  float widthPx = 1.5f;
  float opacity = 1.0f;
};

struct MapFrameStats {
  map::GshhgResolution resolution = map::GshhgResolution::Crude;  ///< the finest level in view
  int binsInView = 0;
  std::array<int, 5> binsAtLevel{};  ///< built-in bins drawn at each level (crude .. full)
  int chunksDrawn = 0;
  int chunksBuilt = 0;
  std::size_t segmentsDrawn = 0;
};

class MapRendererGL {
 public:
  /// `gshhgDir`: where the binned GSHHG files are (map::defaultGshhgDirectory()).
  static Result<std::unique_ptr<MapRendererGL>> create(const std::string& gshhgDir);
  ~MapRendererGL();
  MapRendererGL(const MapRendererGL&) = delete;
  MapRendererGL& operator=(const MapRendererGL&) = delete;

  /// Coastlines, country and state borders from GSHHG (on by default). Checks that the crude
  /// files open: an error names the file when they do not (the layers then stay off).
  Status setBuiltinLayers(bool enabled);
  bool builtinLayers() const { return builtin_; }
  /// Styles of the three built-in layers: 0 coast, 1 country borders, 2 state/province borders.
  void setBuiltinStyle(int layer, const MapLineStyle& style) { builtinStyle_[layer] = style; }
  /// Reads a user vector file (GDAL/OGR) and adds it as a layer; returns a line for the user.
  Result<std::string> addOverlay(const std::string& path, const MapLineStyle& style);
  /// Adds lines (range rings, tests) as a layer.
  void addLines(const std::vector<map::GeoPolyline>& lines, const MapLineStyle& style);
  /// Removes every layer added by addLines or addOverlay (lines rebuilt for a new view: wind barbs).
  void clearLines();

  /// Draws into the bound framebuffer (after the globe: depth test on, writes off, blending).
  MapFrameStats draw(const Camera& camera);
  /// Milliseconds a frame may spend reading and building chunks (0, the default: no limit, every
  /// frame complete, as `render` needs). With a budget (at least one chunk a frame is made), chunks
  /// not made in time are made in later frames, the resolution drawn before is drawn meanwhile,
  /// and lastFrameComplete() is false.
  void setBuildBudgetMs(double ms) { buildBudgetMs_ = ms; }
  /// False when the last frame left chunks of its view to make (draw again to finish).
  bool lastFrameComplete() const { return lastFrameComplete_; }

  struct ChunkGL;

 private:
  MapRendererGL() = default;
  struct Overlay {
    std::vector<std::vector<map::GeoPolyline>> pieces;  ///< grouped, each group one chunk
    std::vector<glm::dvec4> spheres;                    ///< per group: centre (ECEF), radius
    MapLineStyle style;
  };
  struct BinSamples {
    glm::dvec3 center{0.0};
    double radius = 0.0;
    std::vector<glm::dvec3> samples;
  };
  struct Wanted;
  using ChunkKey = std::tuple<int, int, int>;  ///< (layer, resolution, bin or group)
  /// The chunks a view wants: built-in bins in view, each at the level its distance asks for
  /// (levelAt), and overlay groups in the frustum; `stats` gets the bins and the finest level.
  std::vector<Wanted> wantedChunks(const Camera& camera, const globe::ViewState& view, MapFrameStats* stats);
  /// The GSHHG level for lines `distanceMeters` from the eye: the coarsest whose published point
  /// spacing is at most two pixels there (map::gshhgResolutionForScale).
  static map::GshhgResolution levelAt(const Camera& camera, double distanceMeters);
  bool binVisible(const Camera& camera, const globe::ViewState& view, const map::GshhgBinBox& box) const;
  const map::GshhgFile* file(map::GshhgKind kind, map::GshhgResolution r);
  void drawChunk(const Camera& camera, const ChunkGL& chunk, const MapLineStyle& style);

  std::string gshhgDir_;
  bool builtin_ = false;
  MapLineStyle builtinStyle_[3];
  ShaderProgramGL program_;
  unsigned int vao_ = 0;
  std::map<std::pair<int, int>, std::unique_ptr<map::GshhgFile>> files_;  ///< (kind, resolution)
  std::map<std::pair<int, int>, bool> fileFailed_;
  /// Cached chunks: key (layer, resolution, bin or group).
  std::map<ChunkKey, std::unique_ptr<ChunkGL>> chunks_;
  std::size_t chunkBytes_ = 0;
  std::vector<Overlay> overlays_;
  std::uint64_t frame_ = 0;
  double buildBudgetMs_ = 0.0;
  /// The chunks of the last view whose every chunk was made (drawn while a new view's are made).
  std::vector<ChunkKey> shown_;
  bool shownValid_ = false;
  bool lastFrameComplete_ = true;
};

}  // namespace atmoglobe::engine
