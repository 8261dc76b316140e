#pragma once
// The ray marcher of every volume kind (shaders/volume_march.frag): marches volumes into an
// internal RGBA16F image, optionally at a lower resolution, occluded by the globe's depth, and
// lays it over the frame (premultiplied). Several volumes are marched together where they can
// overlap, so that the picture is the emission-absorption integral of all of them (extinctions
// add, colours weighted by extinction), the rule of the CPU reference
// (volume/ReferenceRenderer.h). docs/volume-rendering.md.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/FarFieldGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/engine/VolumeGL.h>
#include <atmoglobe/volume/RenderCamera.h>
#include <atmoglobe/volume/VolumeImage.h>

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace atmoglobe::engine {

/// Appends what a transfer function's tables are made from (its opacity ramp and points, colour
/// stops, offset and scale) to `key`: the marcher's transfer rows and the far field's slabs are
/// made again when it changes.
void appendTransferKey(const volume::TransferFunction& tf, std::vector<double>& key);

/// The reference renderer's camera for an engine camera (same convention, plain data).
volume::RenderCamera referenceCameraFor(const Camera& camera);

/// One volume of a draw: the GPU volume (not owned) and its options.
struct VolumeLayerGL {
  VolumeLayerGL(const VolumeGL* v = nullptr, VolumeRenderOptions o = {}, std::optional<volume::LonLatBox> h = {})
      : volume(v), options(std::move(o)), hole(std::move(h)) {}
  const VolumeGL* volume = nullptr;
  VolumeRenderOptions options;
  /// Where the volume has no data in this frame (a grid's far part around the finer near part
  /// drawn with it: GridSourceGL): sample_grid.glsl's VOL_hole on the GPU,
  /// volume::SamplerOutsideBox in the reference. Only grids honour it.
  std::optional<volume::LonLatBox> hole;
};

/// A march program variant: what is compiled into one program.
struct MarchVariant {
  int mode = 0;  ///< 0 DVR, 1 MIP, 2 isosurface, 3 debug (volume 0's coordinates)
  bool skipEmpty = true;
  bool preintegrated = false;
  /// Some volume follows the step rule (samplesPerCell > 0, volume/StepRule.h); without, the
  /// rule's code folds away and the march is the fixed-step one.
  bool stepRule = false;
  /// The refinement pass of adaptive refinement (VolumeRenderOptions::refineThreshold): pixels
  /// whose small-image neighbourhood agrees take its bilinear value, the others are marched.
  bool adaptive = false;
  /// The far field's columns (FarFieldGL.h): pixels are columns down the vertical, not camera rays.
  bool columns = false;
  /// Measurement: the same march, writing per pixel the samples it took (one per volume per
  /// position sampled, the isosurface's bisection and gradient included) instead of the image.
  bool countSamples = false;
  /// Per volume: its sampler file and its sampler defines.
  std::vector<std::pair<std::string, std::vector<std::string>>> volumes;
  auto operator<=>(const MarchVariant&) const = default;
};

class VolumeRendererGL {
 public:
  static Result<std::unique_ptr<VolumeRendererGL>> create();
  ~VolumeRendererGL();

  /// Draws the layers over `target` (reverse-Z depth of the frame occludes them) and leaves
  /// `target` bound. Volumes whose bounding spheres are apart are drawn in separate passes
  /// (clusters, volume::clusterBySphere), back to front, each limited to its projected bounding
  /// box: exact, since along any ray one cluster lies wholly before another. Within a cluster,
  /// layers are marched together in groups: consecutive layers with the same mode, step, early
  /// termination, classification, skipping and image scale, up to MarchConstants::kMaxVolumes at
  /// a time; groups are composited in layer order. Cost: a pixel pays for the clusters whose box
  /// holds it, and in a cluster samples only inside each volume's own interval (but see
  /// docs/volume-rendering.md: on llvmpipe every sample of a cluster's march costs as much as
  /// sampling each of its volumes).
  ///
  /// A group whose imageScale < 1 and refineThreshold >= 0 is marched twice: at imageScale, then
  /// at full resolution where that image's neighbourhood of a pixel varies by more than the
  /// threshold or straddles the globe's edge (shaders/volume_march.frag, MARCH_ADAPTIVE); the
  /// rest of the pixels take the small image's bilinear value.
  void draw(const Camera& camera, const std::vector<VolumeLayerGL>& layers, const FramebufferGL& target);
  void draw(const Camera& camera, const VolumeGL& volume, const VolumeRenderOptions& options,
            const FramebufferGL& target) {
    draw(camera, {VolumeLayerGL{&volume, options}}, target);
  }

  /// `draw` with the CPU reference renderer (volume::renderReference: double precision, each
  /// kind's exact sampling rule through VolumeGL::referenceSampler) in the marcher's place: the
  /// same groups, occluded by the same depth (read back from `target`), composited the same way,
  /// so that a frame drawn this way differs from a `draw` frame only where the marcher does.
  /// Full resolution whatever imageScale says. Slow (about 1 us per sample per volume).
  void drawReference(const Camera& camera, const std::vector<VolumeLayerGL>& layers, const FramebufferGL& target,
                     int threads);

  /// Progressive refinement (the viewer at rest): the same passes and marches as draw(), the
  /// volume image marched in tiles of kTilePx x kTilePx pixels over several calls, each call
  /// marching tiles until `budgetMs` has passed (at least one), then compositing the volume
  /// image as draw() does. The first call after a change of the camera, the image size, the
  /// layers (their volumes, uniform versions, image scales) or restartProgressive() fills the
  /// image from a march at previewScale(), so tiles not refined yet show that. Once every tile is
  /// marched the frame is draw()'s, pixel for pixel (the same program at the same pixels; tests).
  /// `budgetMs` bounds the call's volume work in all: the work the frame queued before (finished
  /// first), a preview, slabs and tiles; at least a quarter of it goes to slabs or tiles.
  /// While a far field is being made over frames (setFarFieldBuildBudgetMs), the tiles wait: the
  /// call makes slabs within that budget, and a completed set starts the refinement again, drawn
  /// from it. Returns whether every tile is marched.
  bool drawProgressive(const Camera& camera, const std::vector<VolumeLayerGL>& layers, const FramebufferGL& target,
                       double budgetMs);
  void restartProgressive() { progress_.valid = false; }
  /// What the full-quality march of the last view refined costs, in milliseconds: the tiles of the
  /// last finished refinement in all, or, until one finishes, its preview's march time / the
  /// preview scale squared (a march's cost goes with its pixels); 0 before either.
  double fullMarchEstimateMs() const { return fullMarchEstimateMs_; }
  /// Tiles marched and in all, of the refinement under way.
  std::pair<std::size_t, std::size_t> progressiveTiles() const { return {progress_.next, progress_.tiles.size()}; }
  static constexpr int kTilePx = 32;
  /// Refinements whose preview was the last draw()'s image (no march of its own).
  std::size_t previewsReused() const { return previewsReused_; }
  /// Previews marched (one per pass of a refinement that did not reuse one), and the image scale
  /// of the last: previewScale(), or less where the last preview's cost a pixel says that scale
  /// would not fit the call's budget (down to kMinPreviewScale).
  std::size_t previewsMarched() const { return previewsMarched_; }
  double lastPreviewScale() const { return lastPreviewScale_; }
  static constexpr double kPreviewScale = 0.25;
  /// The preview's image scale (kPreviewScale by default; the viewer sets its last moving scale,
  /// so that the last moving frame is the preview: 0.02..1).
  void setPreviewScale(double scale) { previewScale_ = std::clamp(scale, 0.02, 1.0); }
  double previewScale() const { return previewScale_; }
  /// The least preview scale a budget may ask for (the viewer's moving frames' floor).
  static constexpr double kMinPreviewScale = 1.0 / 16.0;
  /// The last group's reference image from drawReference (row 0 = top).
  const volume::VolumeImage& lastReferenceImage() const { return lastReference_; }

  /// Debug/measurement: for each pixel, the kind's coordinates (a radar: range m, azimuth deg,
  /// elevation deg) that the shader computes for the point at distance tMeters along the
  /// pixel's ray. RGBA32F read back, row 0 = top.
  std::vector<glm::vec4> debugCoordinatesAt(const Camera& camera, const VolumeGL& volume, double tMeters);

  /// Measurement: for each pixel, the samples the march of these layers (one group: marched
  /// together, as draw() marches a cluster) takes over an empty background at full resolution:
  /// one per volume per position sampled, after empty-space skipping and early termination as
  /// configured. Row 0 = top. Empty if the program failed.
  std::vector<float> sampleCounts(const Camera& camera, const std::vector<VolumeLayerGL>& layers);

  /// The last volume image composited by draw() (premultiplied RGBA, float; an adaptive pass's
  /// full-resolution image), row 0 = top.
  std::vector<glm::vec4> readVolumeImage() const;

  /// glUniform* calls issued by the marcher so far (its own and its volumes' samplers' uniforms).
  /// A second draw of an unchanged frame issues none: uniforms are set once per change.
  std::uint64_t uniformUploads() const { return uniformUploads_; }

  /// The program of a variant: assembled, compiled on first use and kept. Null with the
  /// compile log on stderr (once) if it fails.
  const ShaderProgramGL* marchProgram(const MarchVariant& variant);

  /// The far field's slab `slab` of `plan` (FarFieldGL.h): one column per pixel of the bound
  /// framebuffer (plan.columns x plan.rows), marched down the vertical through that slab with
  /// the layer's settings at the fixed step. False if the program failed.
  bool marchColumns(const VolumeLayerGL& layer, const FarFieldPlan& plan, int slab);
  /// The far field's slab sets made so far and their GPU bytes (FarFieldGL).
  const FarFieldGL& farField() const { return *farField_; }
  FarFieldGL& farField() { return *farField_; }
  /// The time each draw() or drawProgressive() call may spend making far-field slabs
  /// (FarFieldGL::beginFrame): <= 0 (the default: render, bench) makes them whole when first
  /// needed; the viewer makes them over frames, marching the volume until they are complete.
  void setFarFieldBuildBudgetMs(double ms) { farFieldBuildBudgetMs_ = ms; }
  /// Whether the last draw() or drawProgressive() call left some far field incomplete (the
  /// volume was marched, or drawn from coarser slabs, meanwhile): draw again to complete it.
  bool farFieldPending() const;

 private:
  VolumeRendererGL() = default;
  /// Uniform locations of the march program's own uniforms, resolved once when it is built.
  struct MarchLocationsGL {
    int cameraToEcef = -1, focalPx = -1, imageSizePx = -1, near = -1, step = -1, earlyTermination = -1, debugT = -1,
        coarseSizePx = -1, refineThreshold = -1, columnBox = -1, columnHeights = -1, columnAnchor = -1;
    struct Volume {
      int eyeRel = -1, ecefToLocal = -1, gridMinLocal = -1, gridCellSize = -1, gridCells = -1, isoValue = -1,
          opacityZeroValue = -1, mipVisibleMin = -1, tfRange = -1, isoColor = -1, samplesPerCell = -1, hole = -1;
    };
    std::vector<Volume> volumes;
  };
  /// What a program's uniforms were last set from: each group is set again only on change.
  struct ProgramEntry {
    ShaderProgramGL program;
    UniformCacheGL uniforms;  ///< the samplers' own uniforms (set on change only)
    MarchLocationsGL locations;
    std::vector<float> shared;  ///< camera, step, termination, debug t
    struct Slot {
      std::uint64_t volumeId = 0, uniformVersion = 0;  ///< whose sampler uniforms it holds (0: none)
      std::vector<float> generic;                      ///< eye, grid, iso, transfer range
    };
    std::vector<Slot> slots;
  };
  /// The small image an adaptive refinement pass reads (MarchVariant::adaptive).
  struct CoarseGL {
    unsigned int texture = 0;
    glm::ivec2 sizePx{0};
    double thresholdSteps = 0.0;  ///< 8-bit steps
  };
  /// The far field's columns (MarchVariant::columns).
  struct ColumnsGL {
    glm::vec4 box{0.0f};      ///< lonWestDeg, latSouthDeg, lonStepDeg, latStepDeg
    glm::vec2 heights{0.0f};  ///< the column's top and bottom (m above the ellipsoid)
    glm::vec3 anchor{0.0f};   ///< ECEF of the camera given to march (its eye)
  };
  /// Marches one group into the bound target; false if its program failed. debugMode 1: the
  /// kind's coordinates at debugT (mode 3), 2: the samples taken (MarchVariant::countSamples). `coarse`: the
  /// refinement pass of adaptive refinement over that small image; `columns`: the far field's
  /// columns instead of the camera's rays.
  bool march(const Camera& camera, const VolumeLayerGL* layers, int count, unsigned int depthTexture, int debugMode,
             double debugT, const CoarseGL* coarse = nullptr, const ColumnsGL* columns = nullptr);
  void ensureTarget(int widthPx, int heightPx, unsigned int format);
  /// Whether a pass is drawn from its far field: the plan (prepared: its slabs made, or coarser
  /// ones drawn meanwhile), or none (marched); `hidden` where all of it is behind the Earth.
  struct FarFieldChoice {
    std::optional<FarFieldPlan> plan;
    bool hidden = false;
  };
  FarFieldChoice chooseFarField(const Camera& camera, const std::vector<VolumeLayerGL>& layers);
  /// Clears `box` (x0, y0, x1, y1) of `image` and marches `layers` there (scissored), against the
  /// depth of `target`: draw()'s work per pass, drawProgressive's per preview and tile.
  bool marchBox(const Camera& camera, const std::vector<VolumeLayerGL>& layers, const FramebufferGL& image,
                const glm::ivec4& box, const FramebufferGL& target, const CoarseGL* coarse = nullptr,
                const FarFieldChoice* farField = nullptr);
  /// Whether a group is drawn by adaptive refinement (image scale < 1, threshold >= 0).
  static bool refines(const VolumeRenderOptions& o) { return o.imageScale < 1.0 && o.refineThreshold >= 0.0; }
  /// One past the last layer of the group starting at `begin` (layers one program marches together).
  static std::size_t groupEnd(const std::vector<VolumeLayerGL>& layers, std::size_t begin);
  /// One march and composite: layers marched together, inside a rectangle of the target.
  struct PassGL {
    std::vector<VolumeLayerGL> layers;
    glm::ivec4 rectPx{0};  ///< x, y (GL: from the bottom left), width, height in target pixels
  };
  /// Where a pass's image can hold anything, in target pixels (GL rectangle): a pass drawn from
  /// its far field (`farField`, or where null its plan alone), only the far field's rectangle,
  /// none if it is all behind the Earth; any other pass, its rectangle.
  static glm::ivec4 overRectOf(const Camera& camera, const PassGL& pass, const FramebufferGL& target,
                               const FarFieldChoice* farField);
  /// The passes of a draw, in drawing order: volumes clustered by their bounding spheres
  /// (volume::clusterBySphere), clusters back to front, within a cluster the groups of groupEnd
  /// in layer order; each pass limited to its cluster's projected bounding box.
  static std::vector<PassGL> planPasses(const Camera& camera, const std::vector<VolumeLayerGL>& layers);
  /// Makes (or goes on making, within the frame's budget) the far fields of the passes that would
  /// be drawn from one (FarFieldGL::prepare), before anything is marched.
  void advanceFarFields(const Camera& camera, const std::vector<PassGL>& passes);
  /// Lays a premultiplied volume image (any size: bilinear) over `target` inside `rectPx`;
  /// leaves it bound.
  void compositeOver(unsigned int volumeTexture, const FramebufferGL& target, const glm::ivec4& rectPx);

  std::unique_ptr<FarFieldGL> farField_;
  double farFieldBuildBudgetMs_ = 0.0;
  std::map<MarchVariant, ProgramEntry> programs_;
  std::map<MarchVariant, std::string> programErrors_;
  ShaderProgramGL composite_;
  unsigned int vao_ = 0;
  unsigned int transfer_ = 0;          ///< TRANSFER_ENTRIES x MAX_VOLUMES: each volume's classify() row
  unsigned int transferIntegral_ = 0;  ///< (TRANSFER_ENTRIES + 1) x MAX_VOLUMES, linear: volume::transferIntegralTable
  unsigned int nearestSampler_ = 0;
  std::unique_ptr<FramebufferGL> volumeTarget_;
  std::unique_ptr<FramebufferGL> refineTarget_;  ///< adaptive passes' full-resolution image
  const FramebufferGL* lastImage_ = nullptr;     ///< the image draw() composited last
  /// The refinement under way (drawProgressive): what it is of, a full-scale image per pass, the
  /// tiles (pass, x0, y0, x1, y1 in that image) and how many are marched.
  struct Progress {
    bool valid = false;
    std::vector<double> key;
    std::vector<std::unique_ptr<FramebufferGL>> images;
    /// Per pass: an adaptive pass's small image (marched whole first), else null.
    std::vector<std::unique_ptr<FramebufferGL>> coarse;
    struct Tile {
      std::size_t pass = 0;
      glm::ivec4 box{0};
    };
    std::vector<Tile> tiles;
    /// Per pass: where its image is laid over the frame (overRectOf).
    std::vector<glm::ivec4> overRects;
    std::size_t next = 0;
    double marchedMs = 0.0;  ///< the tiles' time so far
  };
  Progress progress_;
  double fullMarchEstimateMs_ = 0.0;
  bool lastDrawValid_ = false;       ///< draw()'s last call was one pass: volumeTarget_ holds its image
  std::vector<double> lastDrawKey_;  ///< of that call (progressKey)
  std::size_t previewsReused_ = 0;
  double previewScale_ = kPreviewScale;
  /// The last preview march's cost per volume-image pixel (ms; 0: none yet): a preview is marched
  /// at a smaller scale (down to kMinPreviewScale) where previewScale_ would not fit the budget.
  double previewMsPerPixel_ = 0.0;
  std::size_t previewsMarched_ = 0;
  double lastPreviewScale_ = 0.0;
  unsigned int volumeFormat_ = 0;
  unsigned int emptyDepth_ = 0;
  /// The transfer rows last uploaded, per row: what they were made from (uploaded again only on change).
  struct TransferKey {
    const volume::TransferFunction* transfer = nullptr;
    std::vector<double> fingerprint;
    bool operator==(const TransferKey&) const = default;
  };
  std::vector<TransferKey> transferRows_;
  std::uint64_t uniformUploads_ = 0;  ///< glUniform calls issued by march (tests: a static frame issues none)
  volume::VolumeImage lastReference_;
};

}  // namespace atmoglobe::engine
