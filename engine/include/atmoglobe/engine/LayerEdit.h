#pragma once
// What an edit of a volume layer in the viewer's control panel needs, GL-free: the colour tables
// the panel offers, the draw order edits, and how memory is written (whether an edit needs the
// data read again: layerChange in VolumeLayer.h). SceneRendererGL applies the edits
// (setVolumeDescription, setVolumeOrder).
#include <atmoglobe/engine/Scene.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace atmoglobe::engine {

/// The colour tables a layer can take by name (volume::transferForField): "auto" first.
const std::vector<std::string>& colorTableChoices();

/// `order` with the entry at `position` moved by `delta` places (clamped to the ends); the
/// others keep their relative order. Out-of-range position: unchanged.
std::vector<std::size_t> moveInOrder(std::vector<std::size_t> order, std::size_t position, int delta);

/// A byte count for people: "512 B", "12.3 KiB", "4.0 MiB", "1.25 GiB".
std::string formatBytes(std::uint64_t bytes);

}  // namespace atmoglobe::engine
