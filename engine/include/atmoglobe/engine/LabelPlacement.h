#pragma once
// Where marker labels go so that they do not pile up (GL-free; MarkerRendererGL draws them).
//
// Greedy placement by priority: candidates are taken highest priority first (ties: input
// order). Each tries, in order, the slots beside its marker: right, left, above, below, then the
// four diagonal corners; a slot is taken when the label's box lies wholly inside the image and
// overlaps no box placed before and no marker disc (the label's own disc excepted); when no slot
// is free, the slots are tried again allowing the label to cover discs of markers of strictly
// lower priority (so a radar keeps its name among dense stations). A label with no slot left is
// dropped (the marker is still drawn). The result is a set of boxes no two of
// which overlap, so every placed label is readable; which labels survive is decided by priority.
// This is the classic greedy heuristic of cartographic label placement (the optimum is
// NP-hard); it is O(n^2) in the labels, ~0.1 ms for the 160 NEXRAD sites.
#include <cstddef>
#include <vector>

namespace atmoglobe::engine {

/// An axis-aligned box in pixels (y down), [left, left + width) x [top, top + height).
struct LabelBox {
  double leftPx = 0.0, topPx = 0.0, widthPx = 0.0, heightPx = 0.0;
  bool overlaps(const LabelBox& o) const {
    return leftPx < o.leftPx + o.widthPx && o.leftPx < leftPx + widthPx && topPx < o.topPx + o.heightPx &&
           o.topPx < topPx + heightPx;
  }
};

struct LabelCandidate {
  double anchorXPx = 0.0, anchorYPx = 0.0;  ///< the marker's centre (px)
  double markerRadiusPx = 0.0;              ///< half the marker's diameter (px)
  double widthPx = 0.0, heightPx = 0.0;     ///< the label's box, halo included (px)
  double priority = 0.0;                    ///< higher: placed first
};

enum class LabelSlot { Right, Left, Above, Below, AboveRight, BelowRight, AboveLeft, BelowLeft };

struct PlacedLabel {
  std::size_t candidate = 0;  ///< index into the candidates
  LabelBox box;
  LabelSlot slot = LabelSlot::Right;
};

struct LabelPlacementOptions {
  double imageWidthPx = 0.0, imageHeightPx = 0.0;
  double gapPx = 2.0;  ///< between a marker's disc and its label
};

/// The box of candidate `c` in `slot`.
LabelBox labelBoxAt(const LabelCandidate& c, LabelSlot slot, double gapPx);

/// The labels that fit, in placement order (highest priority first). See the file comment.
std::vector<PlacedLabel> placeLabels(const std::vector<LabelCandidate>& candidates,
                                     const LabelPlacementOptions& options);

}  // namespace atmoglobe::engine
