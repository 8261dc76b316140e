#pragma once
// The far field of a volume seen from far away (docs/networks.md, "The far field"): a radar
// network seen from a continent away covers hundreds of thousands of pixels, and marching each
// of them through every radar over it costs about 100 times one radar's frame. Where every
// pixel over the volume spans kMinFootprintMeters or more, the volume is drawn instead from its
// far field:
//  1. Slabs. The marcher (volume_march.frag, MARCH_COLUMNS) integrates the volume's emission and
//     absorption down the ellipsoid's normal through horizontal slabs (boundaries kSlabBoundariesMeters
//     and the volume's top), one column per texel of a latitude/longitude grid over the volume's
//     extent whose texels are no wider than half the pixels' footprint: premultiplied RGBA per slab.
//     Made once per volume, transfer function, step and texel size, and kept. Made whole when
//     first needed (render, bench), or, with a budget a frame (the viewer), in bands (kBandBlock) over
//     frames: until they are complete the volume is drawn from coarser slabs of the same settings
//     made before, or else marched. Once complete, the slabs are merged in pairs into levels of
//     thicker slabs (levelsOf), up to one over the whole column.
//  2. Per pixel (shaders/far_field.frag), from the thickest level whose slabs span at most a
//     quarter of the pixel across its ray, the ray's piece in each slab takes the slab's texel at
//     the piece's middle (seen slantwise, in sub-pieces that each run at most a pixel sideways),
//     its optical depth scaled by the piece's length over the slab's thickness, composited front
//     to back down to the globe's depth. A pixel whose ray crosses only empty columns (the slabs'
//     mask: a pyramid of "anything in this column", made when a set is complete) draws nothing
//     without visiting the slabs.
// What it assumes: along a ray's piece in a slab the volume is as it is down the vertical at the
// piece's middle. Its error against the march is measured (tests, bench), not bounded here.
// DVR only (point or pre-integrated classification); MIP and isosurfaces are marched.
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ShaderProgramGL.h>
#include <atmoglobe/engine/VolumeGL.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace atmoglobe::engine {

class VolumeRendererGL;
struct VolumeLayerGL;

/// What one far field is made of.
struct FarFieldPlan {
  /// How the camera sees the box (not part of what the slabs are).
  struct View {
    std::optional<glm::dvec4> rect;  ///< frame pixels (x0, y0, x1, y1 from the top left) that can see it; none: none
    double maxIncidenceDeg = 0.0;    ///< the largest angle from the vertical at which the eye sees its ground
    /// Whether a ray's piece of some slab may run more than a pixel's width sideways (the
    /// thickest slab x tan(maxIncidenceDeg) over the narrowest pixel's width): then pieces are cut
    /// into sub-pieces that each run at most a pixel's width (shaders/far_field.frag).
    bool subPieces = false;
  };
  View view;
  double westDeg = 0.0, southDeg = 0.0;       ///< the texel grid's corner
  double lonStepDeg = 0.0, latStepDeg = 0.0;  ///< a texel's size
  int columns = 0, rows = 0;
  std::vector<double> boundariesMeters;  ///< the slabs' boundaries above the ellipsoid, from the top down (slabs + 1)
  int slabCount() const { return static_cast<int>(boundariesMeters.size()) - 1; }
};

/// The slabs at one level of thickness (FarFieldGL::levelsOf): level 0 is the plan's slabs; each
/// level above merges the slabs of the one below in pairs from the ground up (an odd one left at
/// the top stays as it is), down to one slab over the whole column.
struct FarFieldLevel {
  struct Slab {
    int layer = 0;  ///< the slab texture's layer
    double topMeters = 0.0, bottomMeters = 0.0;
    /// For a merged slab: the layers of the level below merged (upper, lower); -1: made by the march
    /// or carried over.
    int upperLayer = -1, lowerLayer = -1;
  };
  std::vector<Slab> slabs;  ///< from the top down
  double thickestMeters = 0.0;
};

class FarFieldGL {
 public:
  /// The narrowest a pixel over the volume may be for the far field (Auto): the network's cells
  /// are 1-2 km (1 km gates, 0.5-1 deg between rays at 100-230 km), and a ray's slant piece
  /// through a 2 km slab moves under 2.4 km sideways up to 50 deg from the vertical.
  static constexpr double kMinFootprintMeters = 2000.0;
  /// Slab boundaries (m above the ellipsoid) up to the volume's top, which closes the last slab.
  static constexpr std::array<double, 9> kSlabBoundariesMeters{0.0,     2000.0,  4000.0,  6000.0, 8000.0,
                                                               10000.0, 12000.0, 15000.0, 20000.0};
  static constexpr int kMaxSlabs = static_cast<int>(kSlabBoundariesMeters.size());
  /// Texels per side at most, and per slab (2^21 texels: 16 MB a slab at RGBA16F).
  static constexpr int kMaxTexels = 4096;
  static constexpr double kMaxTexelsPerSlab = 2097152.0;
  /// The slabs kept in all (the least recently used go first), GPU bytes.
  static constexpr std::size_t kMaxKeptBytes = std::size_t{512} << 20;
  /// The most a slab's thickness may span across a ray, in pixels: thickness x sin(the largest
  /// angle from the vertical at which the eye sees the box's ground) over the narrowest pixel's
  /// width (the far field is marched otherwise). One pixel: at half a pixel, the continental
  /// view's 3 km slab (12-15 km) seen 65 deg from the vertical under 5 km pixels was marched.
  static constexpr double kMaxSlabAcrossPixels = 1.0;
  /// The most levels of merged slabs (9 slabs: 9, 5, 3, 2, 1).
  static constexpr int kMaxLevels = 5;
  /// The most slabs over all levels.
  static constexpr int kMaxLevelSlabs = 20;
  /// The most sub-pieces a ray's piece of a slab is cut into (each runs at most a pixel's width
  /// sideways; shaders/far_field.frag).
  static constexpr int kMaxSubPieces = 64;
  /// Slabs made over frames go in bands of one or two blocks of kBandBlock x kBandBlock texels
  /// along a row of blocks, as many as the frame's time left allows at each block's cost in the
  /// slab before (or the last band's). llvmpipe shades in tiles of 64 x 64 pixels: bands of a row
  /// of 2078 texels cost 4-11 ms, blocks of 4096 texels 0.7-2 ms, over storms up to 20 ms (159
  /// radars at 1280x720; docs/networks.md).
  static constexpr int kBandBlock = 64;
  /// Levels of a mask at most (a side of at most 2^21 texels: 22 levels).
  static constexpr int kMaxMaskLevels = 24;
  /// Blocks a band may take (two: llvmpipe's two threads each shade one).
  static constexpr int kMaxBandBlocks = 2;
  /// Volumes whose slabs are kept (the least recently used go first): the 159 NEXRAD sites are 9
  /// clusters.
  static constexpr std::size_t kKeptVolumes = 16;

  static Result<std::unique_ptr<FarFieldGL>> create();
  ~FarFieldGL();
  FarFieldGL(const FarFieldGL&) = delete;
  FarFieldGL& operator=(const FarFieldGL&) = delete;

  /// The far field of `layer` under `camera`, or none: off, not DVR, a kind without a far-field
  /// extent, the eye not above its top, some pixel over the volume narrower than
  /// kMinFootprintMeters (the eye's distance to its bounding sphere, or its height above the top,
  /// whichever is more, / the focal length in pixels), or a slab seen across the ray wider than
  /// kMaxSlabAcrossPixels. A plan whose view.rect is empty draws nothing (it is behind the Earth).
  static std::optional<FarFieldPlan> planFor(const Camera& camera, const VolumeLayerGL& layer);

  /// Starts a frame in which making slabs may take `budgetMs` in all (wall time, the GPU
  /// finished after each band). <= 0: no limit, a volume's slabs are made whole when first needed.
  /// With a limit, at least one band of rows is made each frame, so that slabs are completed
  /// however slow the machine.
  void beginFrame(double budgetMs);
  /// Whether, since beginFrame, some volume's slabs were not complete when asked for.
  bool pending() const { return pending_; }

  /// Makes (or goes on making, within the frame's budget) the slabs of `layer` for `plan`, unless
  /// those kept for that volume, transfer function, step and slabs have texels as fine or finer;
  /// `marcher` marches the columns. Returns whether draw() has slabs for it: those of the plan,
  /// or while they are being made, coarser ones of the same settings made before; false: march
  /// it. Leaves no framebuffer bound.
  bool prepare(VolumeRendererGL& marcher, const VolumeLayerGL& layer, const FarFieldPlan& plan);
  /// Draws the slabs prepare() chose for `layer` into the bound framebuffer (its viewport and
  /// scissor as set, within `view.rect`, the current plan's view), premultiplied, occluded by
  /// `depthTexture` (reverse-Z of the frame).
  void draw(const Camera& camera, const VolumeLayerGL& layer, const FarFieldPlan::View& view,
            unsigned int depthTexture);

  /// The levels of a slab set's mask from its level 0 (`width` x `height`, row by row): level l is
  /// max(1, width >> l) x max(1, height >> l), as GL sizes them, down to 1 x 1; its texel i covers
  /// texels 2i and 2i + 1 of the level below, its last one the rest (an odd size's last three), so
  /// that level 0's texel x lies in texel min(x >> l, size_l - 1) of level l. Each texel is the
  /// largest it covers.
  static std::vector<std::vector<std::uint8_t>> maskPyramid(std::vector<std::uint8_t> level0, int width, int height);
  /// Where each level of a mask of `width` x `height` lies in the one-level texture that holds them
  /// all (the far-field pass reads a level per pixel, and llvmpipe's textureSize(sampler, level)
  /// is wrong where the level varies between pixels, so the levels are regions of one GL level):
  /// level 0 at the corner, the coarser ones side by side along the longer side, past the shorter.
  struct MaskAtlas {
    int width = 0, height = 0;               ///< the texture's size
    std::vector<std::array<int, 4>> levels;  ///< per level: x, y, width, height in the texture
  };
  static MaskAtlas maskAtlas(int width, int height);
  /// The levels of merged slabs for `boundariesMeters` (the plan's, from the top down): level 0
  /// takes layers 0..slabs-1, each merged slab a further layer. A pixel draws from the thickest
  /// level whose slabs span at most half its width across its ray (shaders/far_field.frag).
  static std::vector<FarFieldLevel> levelsOf(const std::vector<double>& boundariesMeters);
  /// Whether pixels may draw from merged slabs (on by default; tests draw both ways and compare).
  void setMergedLevels(bool on) { mergedLevels_ = on; }
  /// Whether pixels may skip the slabs where the mask says their ray crosses only empty columns
  /// (on by default; tests draw both ways and compare).
  void setMaskSkipping(bool on) { maskSkipping_ = on; }

  /// Slab sets completed so far (tests: a second frame of the same view makes none).
  std::size_t slabSetsMade() const { return made_; }
  /// Bands marched so far (tests: a set made over frames).
  std::size_t bandsMarched() const { return bands_; }
  /// GPU bytes of the slabs kept and being made.
  std::size_t gpuBytes() const;

 private:
  FarFieldGL() = default;
  struct Slabs {
    std::uint64_t uniformVersion = 0;
    std::vector<double> settings;  ///< the transfer function, step, classification
    FarFieldPlan plan;
    unsigned int texture = 0;  ///< 0: none
    unsigned int mask = 0;     ///< R8, every level in one (maskAtlas): 1 where a column holds anything; 0: none
    /// Made so far: whole slabs from the top, then rows of the next, then columns of its next
    /// block of rows (kBandBlock rows, or those left).
    int slabsDone = 0, rowsDone = 0, columnsDone = 0;
    /// Made over frames: each block's cost (ms a texel) in the slab being made and in the slab
    /// before (0: not measured), row-major over blocks of kBandBlock x kBandBlock texels.
    std::vector<double> costNow, costBefore;
    int layers = 0;           ///< the texture's layers: every level's slabs
    int mergesDone = 0;       ///< merged slabs made (after every slab of level 0)
    int maskRowsDone = 0;     ///< rows of the mask's level 0 made
    bool maskFailed = false;  ///< no memory for a mask
  };
  /// A volume's slabs: the latest complete set (drawn), and the set being made (not drawn yet).
  struct Kept {
    std::uint64_t volumeId = 0;
    std::uint64_t usedInFrame = 0;  ///< the frame (beginFrame's count) that last asked for it
    Slabs ready, building;
  };
  /// Frees the least recently used volume's slabs not asked for in this frame; false if none.
  bool evictOne();
  std::vector<Kept>::iterator findKept(std::uint64_t volumeId);
  static std::vector<double> settingsKey(const VolumeLayerGL& layer);
  using BoxView = FarFieldPlan::View;
  static BoxView viewOf(const Camera& camera, const FarFieldPlan& plan);
  static void release(Slabs& s);
  /// Marches bands of `s` within the frame's budget; false if the program failed.
  bool build(VolumeRendererGL& marcher, const VolumeLayerGL& layer, Slabs& s);
  /// The mask of a complete set: level 0 on the GPU from the slabs (in bands of rows within the
  /// frame's budget), then the coarser levels on the CPU (maskPyramid). True once made, or once
  /// out of memory (no mask: the pixels then visit the slabs).
  bool makeMask(Slabs& s);
  /// The merged slabs of a complete level 0, one a pass within the frame's budget (at least one a
  /// frame); true once all are made.
  bool makeMerged(Slabs& s);
  ShaderProgramGL program_, subPiecesProgram_, maskProgram_, mergeProgram_;
  bool mergedLevels_ = true;
  unsigned int vao_ = 0, fbo_ = 0;
  std::vector<Kept> kept_;  ///< per volume (a few volumes), the least recently used first
  std::size_t made_ = 0, bands_ = 0;
  double budgetMs_ = 0.0, spentMs_ = 0.0;  ///< this frame's
  int bandsThisFrame_ = 0;
  bool pending_ = false;
  bool maskSkipping_ = true;
  std::uint64_t frame_ = 0;  ///< beginFrame calls
  double msPerTexel_ = 0.0;  ///< the last band's cost (0: none measured yet)
};

}  // namespace atmoglobe::engine
