#pragma once
// A slice drawn on the globe (a scene's "slices"): which volume, which slice, how coloured.
// GL-free: parsed and validated here, sampled through volume/SliceSource.h, drawn by
// SliceRendererGL.
//
// JSON (one object per slice; every key but the source and the slice optional):
//   {"radar": "KTLX.nc" | "grid": "model.nc",            // the volume (read for the slice)
//    "field": "DBZ", "time": "2020-05-01T21:00:00Z",      // field or grid variable; grid time
//    "height_m": 3000 | "path": [[lat, lon], [lat, lon], ...],  // a CAPPI or a cross-section
//    "box": [south, north, west, east],                   // CAPPI box (default: the volume's extent)
//    "heights_m": [bottom, top],                          // cross-section heights
//    "datum": "msl" | "ellipsoid", "colors": "auto", "range": [min, max],
//    "opacity": 1.0, "resolution_px": 512, "geoid": true}
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/Slice.h>
#include <atmoglobe/volume/SliceSource.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::engine {

struct SliceLayerDescription {
  volume::SliceSourceOptions source;  ///< radar or grid, path, field / variable, time, geoid
  volume::SliceRequest request;       ///< CAPPI or cross-section (columns/rows from resolutionPx)
  std::string colors = "auto";        ///< as a radar's or grid's colours (the 3-D view's table)
  std::optional<volume::ValueRange> range;
  double opacity = 1.0;    ///< of the echo pixels, 0..1 (no echo and no data are transparent)
  int resolutionPx = 512;  ///< raster pixels along the slice's longer side (64..4096)
};

/// Checks a slice: a source path, a CAPPI height or a path of two or more points, opacity in
/// 0..1, resolution in 64..4096.
Status validateSliceLayer(const SliceLayerDescription& slice, const std::string& where);

/// Parses the "slices" array of a scene (its JSON text); paths resolved as the scene's
/// (relative to baseDir, "@data" -> dataDir). Errors name `where` ("scene.json: slices[1]").
Result<std::vector<SliceLayerDescription>> parseSliceLayersJson(std::string_view jsonArray, const std::string& where,
                                                                const std::string& baseDir, const std::string& dataDir);

}  // namespace atmoglobe::engine
