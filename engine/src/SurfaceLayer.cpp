// A 2-D field layer's description and read (SurfaceLayer.h).
#include <atmoglobe/engine/SurfaceLayer.h>
#include <atmoglobe/volume/GridReader.h>

#include <cmath>

namespace atmoglobe::engine {

Status validateSurfaceLayer(const SurfaceLayerDescription& d, const std::string& where) {
  if (d.path.empty()) return makeError(where + ": empty path");
  if (!(d.opacity >= 0.0 && d.opacity <= 1.0)) return makeError(where + ": opacity must be in 0..1");
  if (d.pressureHpa && !(*d.pressureHpa > 0.0 && *d.pressureHpa <= 1100.0))
    return makeError(where + ": pressure level must be in (0, 1100] hPa");
  if (d.valueRange &&
      !(std::isfinite(d.valueRange->x) && std::isfinite(d.valueRange->y) && d.valueRange->x < d.valueRange->y))
    return makeError(where + ": range must be two finite numbers, the first below the second");
  if (d.contourInterval && !(*d.contourInterval > 0.0 && std::isfinite(*d.contourInterval)))
    return makeError(where + ": contour interval must be a finite number > 0");
  for (double v : d.contourValues)
    if (!std::isfinite(v)) return makeError(where + ": contour values must be finite");
  if (d.contourInterval && !d.contourValues.empty())
    return makeError(where + ": give a contour interval or contour values, not both");
  if (!d.fill && !d.contourInterval && d.contourValues.empty())
    return makeError(where + ": nothing to draw: no fill and no contours");
  if (!(d.contourWidthPx >= 0.5f && d.contourWidthPx <= 16.0f))
    return makeError(where + ": contour width must be in 0.5..16 px");
  if (d.member >= 0 && !d.ensemble.empty())
    return makeError(where + ": give a member or an ensemble statistic, not both");
  if (!d.ensemble.empty())
    if (auto e = volume::parseEnsembleStatistic(d.ensemble); !e) return makeError(where + ": " + e.error());
  return Ok{};
}

Result<volume::SurfaceField> readSurfaceField(const SurfaceLayerDescription& d) {
  volume::GridReadOptions read;
  read.variable = d.variable;
  read.member = d.member;
  read.useGeoid = d.useGeoid;
  read.allowSingleLevel = true;  // surface and single-level fields are what a map shows
  if (!d.ensemble.empty()) {
    auto e = volume::parseEnsembleStatistic(d.ensemble);
    if (!e) return makeError(d.path + ": " + e.error());
    read.ensemble = *e;
  }
  if (!d.time.empty())
    if (Status st = volume::selectGridTime(d.time, read); !st) return makeError(d.path + ": " + st.error());
  auto grid = volume::readGridVolume(d.path, read);
  if (!grid) return grid.forwardError();
  std::optional<double> pressurePa;
  if (d.pressureHpa) pressurePa = *d.pressureHpa * 100.0;
  return volume::surfaceFieldOf(std::move(*grid), pressurePa);
}

}  // namespace atmoglobe::engine
