#include <atmoglobe/engine/LabelPlacement.h>

#include <algorithm>
#include <numeric>

namespace atmoglobe::engine {

LabelBox labelBoxAt(const LabelCandidate& c, LabelSlot slot, double gapPx) {
  const double r = c.markerRadiusPx + gapPx;
  // The diagonal slots sit clear of the disc's bounding square, the side ones centred on it.
  const double d = r * 0.7071;
  LabelBox b{0.0, 0.0, c.widthPx, c.heightPx};
  switch (slot) {
    case LabelSlot::Right: b.leftPx = c.anchorXPx + r, b.topPx = c.anchorYPx - 0.5 * c.heightPx; break;
    case LabelSlot::Left: b.leftPx = c.anchorXPx - r - c.widthPx, b.topPx = c.anchorYPx - 0.5 * c.heightPx; break;
    case LabelSlot::Above: b.leftPx = c.anchorXPx - 0.5 * c.widthPx, b.topPx = c.anchorYPx - r - c.heightPx; break;
    case LabelSlot::Below: b.leftPx = c.anchorXPx - 0.5 * c.widthPx, b.topPx = c.anchorYPx + r; break;
    case LabelSlot::AboveRight: b.leftPx = c.anchorXPx + d, b.topPx = c.anchorYPx - d - c.heightPx; break;
    case LabelSlot::BelowRight: b.leftPx = c.anchorXPx + d, b.topPx = c.anchorYPx + d; break;
    case LabelSlot::AboveLeft: b.leftPx = c.anchorXPx - d - c.widthPx, b.topPx = c.anchorYPx - d - c.heightPx; break;
    case LabelSlot::BelowLeft: b.leftPx = c.anchorXPx - d - c.widthPx, b.topPx = c.anchorYPx + d; break;
  }
  return b;
}

std::vector<PlacedLabel> placeLabels(const std::vector<LabelCandidate>& candidates, const LabelPlacementOptions& o) {
  std::vector<std::size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return candidates[a].priority > candidates[b].priority; });
  std::vector<LabelBox> discs;
  discs.reserve(candidates.size());
  for (const LabelCandidate& c : candidates)
    discs.push_back({c.anchorXPx - c.markerRadiusPx, c.anchorYPx - c.markerRadiusPx, 2.0 * c.markerRadiusPx,
                     2.0 * c.markerRadiusPx});
  std::vector<PlacedLabel> placed;
  for (std::size_t i : order) {
    const LabelCandidate& c = candidates[i];
    if (!(c.widthPx > 0.0 && c.heightPx > 0.0)) continue;
    // First a slot that covers no marker; failing that, one that covers only markers of lower
    // priority (a radar's name over a station's dot rather than no name at all).
    for (const bool coverLower : {false, true}) {
      bool done = false;
      for (LabelSlot slot :
           {LabelSlot::Right, LabelSlot::Left, LabelSlot::Above, LabelSlot::Below, LabelSlot::AboveRight,
            LabelSlot::BelowRight, LabelSlot::AboveLeft, LabelSlot::BelowLeft}) {
        const LabelBox b = labelBoxAt(c, slot, o.gapPx);
        if (b.leftPx < 0.0 || b.topPx < 0.0 || b.leftPx + b.widthPx > o.imageWidthPx ||
            b.topPx + b.heightPx > o.imageHeightPx)
          continue;
        bool free = std::none_of(placed.begin(), placed.end(), [&](const PlacedLabel& p) { return p.box.overlaps(b); });
        for (std::size_t k = 0; free && k < discs.size(); ++k)
          if (k != i && discs[k].overlaps(b) && !(coverLower && candidates[k].priority < c.priority)) free = false;
        if (free) {
          placed.push_back({i, b, slot});
          done = true;
          break;
        }
      }
      if (done) break;
    }
  }
  return placed;
}

}  // namespace atmoglobe::engine
