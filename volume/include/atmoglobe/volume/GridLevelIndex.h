// Where a height lies among a grid's levels in one fetch, not a search (the GPU marcher's level
// lookup; docs/grids.md, "The level of a sample").
#pragma once

#include <atmoglobe/volume/GridSampler.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace atmoglobe::volume {

/// For every cell of a grid's closed columns (the 2 x 2 columns (tc..tc+1, tr..tr+1), or for a
/// reduced grid the pair (tc, tc+1) of row tr) and every height bin, the levels a sample there can
/// lie between: [loMin, loMax + 1] holds the level pair (lo, lo + 1) of every blend of the cell's
/// columns at every height of the bin, as the GPU blends the columns' float heights. The sampler
/// then bisects within that bracket (usually 0 or 1 steps) instead of among all the levels.
///
/// Height bins follow the grid's levels: the mean level height profile over the columns gives each
/// height a fractional "reference level", tabulated at `heightEntries` equal height steps from
/// minHeightMeters to maxHeightMeters and interpolated linearly; a height's bin is
/// floor(reference level x binsPerLevel) clamped to [0, bins - 1]. binOf is that rule in double;
/// each bin's bracket holds for heights a margin beyond the bin, more than the float evaluation
/// of the same rule can move a height across a bin's edge.
struct GridLevelIndex {
  double minHeightMeters = 0.0, maxHeightMeters = 0.0;
  std::vector<float> referenceLevelAtHeight;  ///< heightEntries values
  double binsPerLevel = 1.0;
  int bins = 1;
  glm::ivec2 cells{0};    ///< closed columns, closed rows (the last column and row: alone or clamped)
  bool rowPairs = false;  ///< a reduced grid: each cell is (tc, tc + 1) in row tr
  int levels = 0;         ///< nz
  /// (tr * cells.x + tc) * bins + bin: loMin, and loMax - loMin (kToTop when it reaches the top).
  std::vector<std::uint8_t> loMin, span;
  static constexpr int kToTop = 15;  ///< a span this wide or wider: up to the top level pair
  static constexpr int kMaxLevels = 256;

  int heightEntries() const { return static_cast<int>(referenceLevelAtHeight.size()); }
  /// The bin of a height (the shader's rule, in double).
  int binOf(double heightMeters) const;
  /// The level pairs [lo, hi - 1] a sample of cell (tc, tr) at this bin can lie in: lo <= hi - 1.
  glm::ivec2 bracket(int tc, int tr, int bin) const;
};

/// The index of a sampler's closed columns (at most kMaxLevels levels; else an index of one bin
/// whose brackets are all the levels). `heightEntries` >= 2 equal height steps tabulate the
/// reference level; `binsPerLevel` bins per reference level interval (capped to 64 bins).
GridLevelIndex buildGridLevelIndex(const GridSampler& sampler, int heightEntries = 4096, double binsPerLevel = 1.0);

/// How tight the brackets are: the mean number of bisection steps a sample takes (ceil(log2(span
/// + 1))), over every cell and bin, and the largest.
struct GridLevelIndexStats {
  double meanSteps = 0.0;
  int maxSteps = 0;
};
GridLevelIndexStats gridLevelIndexStats(const GridLevelIndex& index);

}  // namespace atmoglobe::volume
