// The level lookup of a grid's closed columns (GridLevelIndex.h).
#include <atmoglobe/volume/GridLevelIndex.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace atmoglobe::volume {

int GridLevelIndex::binOf(double heightMeters) const {
  const int entries = heightEntries();
  if (entries < 2 || !(maxHeightMeters > minHeightMeters)) return 0;
  const double x = (heightMeters - minHeightMeters) / (maxHeightMeters - minHeightMeters) * (entries - 1);
  const int e = std::clamp(static_cast<int>(std::floor(x)), 0, entries - 2);
  const double f = std::clamp(x - e, 0.0, 1.0);
  const double level = referenceLevelAtHeight[static_cast<std::size_t>(e)] * (1.0 - f) +
                       referenceLevelAtHeight[static_cast<std::size_t>(e) + 1] * f;
  return std::clamp(static_cast<int>(std::floor(level * binsPerLevel)), 0, bins - 1);
}

glm::ivec2 GridLevelIndex::bracket(int tc, int tr, int bin) const {
  const std::size_t i = (static_cast<std::size_t>(tr) * cells.x + tc) * bins + bin;
  const int lo = loMin[i];
  return {lo, span[i] >= kToTop ? levels - 1 : lo + span[i] + 1};
}

namespace {

// The highest level at or below a height in a column of increasing heights (-1: none), for
// every bin edge in increasing order: one pass over the levels.
void levelsAtHeights(const float* heights, int levels, const std::vector<double>& edges, std::vector<int>& out) {
  out.resize(edges.size());
  int k = -1;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    while (k + 1 < levels && static_cast<double>(heights[k + 1]) <= edges[e]) ++k;
    out[e] = k;
  }
}

}  // namespace

GridLevelIndex buildGridLevelIndex(const GridSampler& s, int heightEntries, double binsPerLevel) {
  GridLevelIndex index;
  const glm::ivec3 ts = s.closedSize();
  const int nz = ts.z;
  index.levels = nz;
  index.cells = glm::ivec2(ts.x, ts.y);
  index.rowPairs = s.grid().reduced();
  index.minHeightMeters = s.minHeightMeters();
  index.maxHeightMeters = s.maxHeightMeters();
  const std::size_t cellCount = static_cast<std::size_t>(ts.x) * static_cast<std::size_t>(ts.y);
  heightEntries = std::max(heightEntries, 2);

  // The columns' heights as the GPU holds them (float; closedHeightColumn).
  auto rowHeights = [&](int tr, std::vector<float>& out, std::vector<char>& increasing) {
    out.resize(static_cast<std::size_t>(ts.x) * nz);
    increasing.assign(static_cast<std::size_t>(ts.x), 1);
    for (int tc = 0; tc < ts.x; ++tc) {
      const int column = s.closedHeightColumn(tc, tr);
      float* h = out.data() + static_cast<std::size_t>(tc) * nz;
      for (int k = 0; k < nz; ++k) {
        h[k] = static_cast<float>(s.columnHeight(column, static_cast<std::size_t>(k)));
        // Not strictly increasing (or not finite): the cell's brackets are all the levels, as
        // the full bisection took them.
        if (k > 0 && !(h[k] > h[k - 1])) increasing[static_cast<std::size_t>(tc)] = 0;
      }
      if (!std::isfinite(h[0])) increasing[static_cast<std::size_t>(tc)] = 0;
    }
  };

  // One bin of all levels: too many levels for the 8-bit brackets, or no height range.
  auto allLevels = [&] {
    index.bins = 1;
    index.binsPerLevel = 0.0;
    index.referenceLevelAtHeight.assign(2, 0.0f);
    index.loMin.assign(cellCount, 0);
    index.span.assign(cellCount, GridLevelIndex::kToTop);
    return index;
  };
  if (nz < 2 || nz > GridLevelIndex::kMaxLevels || !(index.maxHeightMeters > index.minHeightMeters)) return allLevels();

  // The reference profile: each level's mean height over the columns (made non-decreasing).
  std::vector<double> meanHeight(static_cast<std::size_t>(nz), 0.0);
  std::size_t counted = 0;
  {
    std::vector<float> hs;
    std::vector<char> inc;
    for (int tr = 0; tr < ts.y; ++tr) {
      rowHeights(tr, hs, inc);
      for (int tc = 0; tc < ts.x; ++tc) {
        if (!inc[static_cast<std::size_t>(tc)]) continue;
        for (int k = 0; k < nz; ++k)
          meanHeight[static_cast<std::size_t>(k)] += hs[static_cast<std::size_t>(tc) * nz + k];
        ++counted;
      }
    }
  }
  if (counted == 0) return allLevels();
  for (int k = 0; k < nz; ++k) {
    double& m = meanHeight[static_cast<std::size_t>(k)];
    m /= static_cast<double>(counted);
    if (k > 0) m = std::max(m, meanHeight[static_cast<std::size_t>(k) - 1]);
  }
  const int bins = std::clamp(static_cast<int>(std::ceil((nz - 1) * binsPerLevel)), 1, 64);
  index.bins = bins;
  index.binsPerLevel = static_cast<double>(bins) / (nz - 1);
  const double dz = (index.maxHeightMeters - index.minHeightMeters) / (heightEntries - 1);
  index.referenceLevelAtHeight.resize(static_cast<std::size_t>(heightEntries));
  for (int e = 0; e < heightEntries; ++e) {
    const double z = index.minHeightMeters + e * dz;
    double level = 0.0;
    if (z >= meanHeight.back()) {
      level = nz - 1;
    } else if (z > meanHeight.front()) {
      const auto it = std::upper_bound(meanHeight.begin(), meanHeight.end(), z);
      const int k = static_cast<int>(it - meanHeight.begin()) - 1;
      const double h0 = meanHeight[static_cast<std::size_t>(k)], h1 = meanHeight[static_cast<std::size_t>(k) + 1];
      level = k + (h1 > h0 ? (z - h0) / (h1 - h0) : 0.0);
    }
    index.referenceLevelAtHeight[static_cast<std::size_t>(e)] = static_cast<float>(level);
  }

  // Each bin's heights [low, high], widened: in bin units by 1e-3 (the float interpolation of the
  // table is good to ~1e-6 of a level), in metres by 1 % of an entry step (the float position in
  // the table) and 0.1 m (the float blend of heights of tens of km is good to ~0.01 m).
  const double binMargin = 1e-3, heightMargin = 0.01 * dz + 0.1;
  std::vector<double> low(static_cast<std::size_t>(bins)), high(static_cast<std::size_t>(bins));
  auto heightOfBinValue = [&](double m, bool first) {
    // The lowest (first) or highest height whose table value x binsPerLevel reaches m.
    for (int e = 0; e + 1 < heightEntries; ++e) {
      const int ee = first ? e : heightEntries - 2 - e;
      const double m0 = index.referenceLevelAtHeight[static_cast<std::size_t>(ee)] * index.binsPerLevel;
      const double m1 = index.referenceLevelAtHeight[static_cast<std::size_t>(ee) + 1] * index.binsPerLevel;
      if (first ? m1 >= m : m0 <= m) {
        const double f = m1 > m0 ? std::clamp((m - m0) / (m1 - m0), 0.0, 1.0) : (first ? 0.0 : 1.0);
        return index.minHeightMeters + (ee + f) * dz;
      }
    }
    return first ? index.maxHeightMeters : index.minHeightMeters;
  };
  for (int b = 0; b < bins; ++b) {
    low[static_cast<std::size_t>(b)] = b == 0 ? -std::numeric_limits<double>::infinity()
                                              : heightOfBinValue(b - binMargin, true) - heightMargin;
    high[static_cast<std::size_t>(b)] = b == bins - 1 ? std::numeric_limits<double>::infinity()
                                                      : heightOfBinValue(b + 1 + binMargin, false) + heightMargin;
  }

  index.loMin.assign(cellCount * bins, 0);
  index.span.assign(cellCount * bins, GridLevelIndex::kToTop);
  // Per column of two consecutive rows: the level at or below each bin's low and high height.
  std::vector<float> h0, h1;
  std::vector<char> inc0, inc1;
  std::vector<int> kLow0, kHigh0, kLow1, kHigh1, tmp;
  auto columnLevels = [&](const std::vector<float>& hs, int tc, std::vector<int>& kLow, std::vector<int>& kHigh) {
    const float* h = hs.data() + static_cast<std::size_t>(tc) * nz;
    levelsAtHeights(h, nz, low, tmp);
    kLow.insert(kLow.end(), tmp.begin(), tmp.end());
    levelsAtHeights(h, nz, high, tmp);
    kHigh.insert(kHigh.end(), tmp.begin(), tmp.end());
  };
  auto rowLevels = [&](int tr, std::vector<float>& hs, std::vector<char>& inc, std::vector<int>& kLow,
                       std::vector<int>& kHigh) {
    rowHeights(tr, hs, inc);
    kLow.clear();
    kHigh.clear();
    for (int tc = 0; tc < ts.x; ++tc) columnLevels(hs, tc, kLow, kHigh);
  };
  rowLevels(0, h0, inc0, kLow0, kHigh0);
  for (int tr = 0; tr < ts.y; ++tr) {
    const bool twoRows = !index.rowPairs && tr + 1 < ts.y;
    if (twoRows) rowLevels(tr + 1, h1, inc1, kLow1, kHigh1);
    // A reduced row's cells reach its last closed column; beyond it, padding (never sampled).
    const int rowColumns = index.rowPairs ? std::max(s.closedRow(tr).columns, 1) : ts.x;
    for (int tc = 0; tc < ts.x; ++tc) {
      const int c0 = std::min(tc, rowColumns - 1), c1 = std::min(tc + 1, rowColumns - 1);
      bool ok = inc0[static_cast<std::size_t>(c0)] && inc0[static_cast<std::size_t>(c1)];
      if (twoRows) ok = ok && inc1[static_cast<std::size_t>(c0)] && inc1[static_cast<std::size_t>(c1)];
      if (!ok) continue;  // all levels
      for (int b = 0; b < bins; ++b) {
        int lo = std::numeric_limits<int>::max(), hi = -1;
        auto take = [&](const std::vector<int>& kLow, const std::vector<int>& kHigh, int c) {
          const std::size_t i = static_cast<std::size_t>(c) * bins + b;
          lo = std::min(lo, kLow[i]);
          hi = std::max(hi, kHigh[i]);
        };
        take(kLow0, kHigh0, c0);
        take(kLow0, kHigh0, c1);
        if (twoRows) {
          take(kLow1, kHigh1, c0);
          take(kLow1, kHigh1, c1);
        }
        lo = std::clamp(lo, 0, nz - 2);
        hi = std::clamp(hi, lo, nz - 2);
        const std::size_t i = (static_cast<std::size_t>(tr) * ts.x + tc) * bins + b;
        index.loMin[i] = static_cast<std::uint8_t>(lo);
        index.span[i] = static_cast<std::uint8_t>(std::min(hi - lo, GridLevelIndex::kToTop));
      }
    }
    if (twoRows) {
      std::swap(h0, h1);
      std::swap(inc0, inc1);
      std::swap(kLow0, kLow1);
      std::swap(kHigh0, kHigh1);
    } else if (tr + 1 < ts.y) {
      rowLevels(tr + 1, h0, inc0, kLow0, kHigh0);
    }
  }
  return index;
}

GridLevelIndexStats gridLevelIndexStats(const GridLevelIndex& index) {
  GridLevelIndexStats st;
  double sum = 0.0;
  for (std::size_t i = 0; i < index.span.size(); ++i) {
    const int pairs = index.span[i] >= GridLevelIndex::kToTop ? index.levels - 1 - index.loMin[i] : index.span[i] + 1;
    const int steps = static_cast<int>(std::ceil(std::log2(static_cast<double>(pairs))));
    sum += steps;
    st.maxSteps = std::max(st.maxSteps, steps);
  }
  if (!index.span.empty()) st.meanSteps = sum / static_cast<double>(index.span.size());
  return st;
}

}  // namespace atmoglobe::volume
