#pragma once
// The logic of the viewer's transfer-function editor, GL-free: a list of opacity control points
// (value in field units, opacity per reference length in [0, 1]; TransferFunction::opacityPoints)
// kept sorted by value while the user adds, moves and deletes points, and picking the point
// under the pointer. The panel (engine/ViewerPanelGL) only maps pixels to (value, opacity) and
// hands the result to volume::withOpacityPoints; reset is volume::opacityCurveOf of the layer's
// unedited transfer function.
#include <glm/glm.hpp>

#include <cstddef>
#include <optional>
#include <vector>

namespace atmoglobe::volume {

/// Inserts `point` (opacity clamped to [0, 1]) in value order; a point of the same value is
/// replaced. Returns its index.
std::size_t addOpacityPoint(std::vector<glm::dvec2>& points, glm::dvec2 point);

/// Moves point `index` to `to`: the opacity clamped to [0, 1], the value kept strictly between
/// its neighbours' (at least `minGap` from each, field units), so the order never changes under
/// a drag. Returns false (nothing changed) for an index out of range.
bool moveOpacityPoint(std::vector<glm::dvec2>& points, std::size_t index, glm::dvec2 to, double minGap);

/// Deletes point `index`; refused (false) when that would leave fewer than two points (a curve
/// needs two) or the index is out of range.
bool deleteOpacityPoint(std::vector<glm::dvec2>& points, std::size_t index);

/// The point nearest `at` within `radiusPx` pixels, distances measured in pixels: value and
/// opacity divided by `unitsPerPixel` (x: field units per pixel, y: opacity per pixel, both > 0).
std::optional<std::size_t> pickOpacityPoint(const std::vector<glm::dvec2>& points, glm::dvec2 at,
                                            glm::dvec2 unitsPerPixel, double radiusPx);

}  // namespace atmoglobe::volume
