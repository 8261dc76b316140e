#pragma once
// What an edit of a volume layer in the viewer's control panel needs, GL-free: whether the
// layer's data must be read again (a different field, variable, time, datum or crop box) or
// only its render options change (colours, opacity, mode, quality knobs), the colour tables
// the panel offers, the draw order edits, and how memory is written. SceneRendererGL applies
// the edits (setRadarDescription, setGridDescription, setVolumeOrder).
#include <atmoglobe/engine/Scene.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace atmoglobe::engine {

enum class LayerChange {
  None,     ///< nothing that shows changed
  Options,  ///< render options only (transfer function, mode, iso value, step, scale, beam...)
  Reload,   ///< the data: the file is read again (field / variable, time, datum, crop box)
};

LayerChange radarLayerChange(const RadarLayerDescription& before, const RadarLayerDescription& after);
LayerChange gridLayerChange(const GridLayerDescription& before, const GridLayerDescription& after);

/// The colour tables a layer can take by name (volume::transferForField): "auto" first.
const std::vector<std::string>& colorTableChoices();

/// `order` with the entry at `position` moved by `delta` places (clamped to the ends); the
/// others keep their relative order. Out-of-range position: unchanged.
std::vector<std::size_t> moveInOrder(std::vector<std::size_t> order, std::size_t position, int delta);

/// A byte count for people: "512 B", "12.3 KiB", "4.0 MiB", "1.25 GiB".
std::string formatBytes(std::uint64_t bytes);

}  // namespace atmoglobe::engine
