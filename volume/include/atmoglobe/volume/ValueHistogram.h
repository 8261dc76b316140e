#pragma once
// A histogram of a volume's values, GL-free: what the viewer's transfer-function editor draws
// its opacity control points over. Echo values (finite) fall into equal bins over [lo, hi];
// no-echo (-inf, kNoEcho) and no-data (NaN, kNoData; also the padding of a polar layout) are
// counted apart, as are finite values outside the span.
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <cstdint>
#include <span>
#include <vector>

namespace atmoglobe::volume {

struct ValueHistogram {
  double lo = 0.0, hi = 1.0;           ///< span of the bins (field units)
  std::vector<std::uint64_t> counts;   ///< bin k: [lo + k w, lo + (k + 1) w), the last bin closed at hi
  std::uint64_t below = 0, above = 0;  ///< finite values < lo, > hi
  std::uint64_t noEcho = 0, noData = 0;
  std::uint64_t largestCount() const;
};

/// The histogram of `values` in `bins` (>= 1) bins over [lo, hi] (lo < hi; otherwise hi is
/// taken as lo + 1).
ValueHistogram valueHistogram(std::span<const float> values, double lo, double hi, int bins);

/// Over a radar's render layout (every sweep; padding gates count as no data) or a grid's
/// values, spanning the volume's measured range (minValue..maxValue; a single value gets a
/// span of 1 around it).
ValueHistogram valueHistogram(const PolarVolume& volume, int bins);
ValueHistogram valueHistogram(const GridVolume& grid, int bins);

}  // namespace atmoglobe::volume
