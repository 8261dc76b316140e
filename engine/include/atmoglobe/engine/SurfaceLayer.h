#pragma once
// A 2-D field of a forecast grid drawn on the globe (scene "surfaces", CLI --surface): what to
// read (file, variable, time, member or ensemble statistic, a pressure level for a 3-D
// variable), the fill (colour table, range, opacity) and contour lines (interval or values,
// labelled). GL-free: SurfaceFieldGL.h draws it; volume/SurfaceField.h is its field and CPU
// reference.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/SurfaceField.h>
#include <atmoglobe/volume/Wind.h>
#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace atmoglobe::engine {

struct SurfaceLayerDescription {
  std::string path;                   ///< resolved (absolute or relative to the working directory)
  std::string variable;               ///< "" : the file's default variable
  std::string time;                   ///< an index ("0") or an ISO 8601 UTC time; "": the first
  int member = -1;                    ///< GRIB `number` (-1: the first)
  std::string ensemble;               ///< "" or mean|spread|min|max|prob:OPV (volume::parseEnsembleStatistic)
  std::optional<double> pressureHpa;  ///< a 3-D variable's isobaric surface
  std::optional<int> level;           ///< or one of its levels (0 = the lowest)
  std::string colors = "auto";        ///< as a grid layer's (volume::transferForField)
  std::optional<glm::dvec2> valueRange;
  double opacity = 0.75;  ///< of the fill, 0..1
  bool fill = true;
  std::optional<double> contourInterval;  ///< contour lines every this many field units
  std::vector<double> contourValues;      ///< or at these values
  glm::vec3 contourColor{0.05f, 0.05f, 0.05f};
  float contourWidthPx = 1.5f;
  bool contourLabels = true;
  /// Wind barbs: "" none, "auto" (the file's u and v: by standard name, eastward_wind / x_wind /
  /// grid_eastward_wind ..., else by name, u/v, 10u/10v, U/V, U10/V10, ua/va ...) or "U,V" (the
  /// two variables). Without a variable, the fill is the wind speed.
  std::string wind;
  glm::vec3 windColor{0.05f, 0.05f, 0.05f};
  bool useGeoid = true;
};

/// What a surface layer draws: its field and, when asked, the wind east and north on the wind's
/// grid (the u component's geometry).
struct SurfaceData {
  volume::SurfaceField field;
  std::optional<volume::GridVolume> windGrid;  ///< nz = 1; values unused
  volume::WindComponents wind;
  std::string windNote;  ///< "wind: u, v (grid-relative, turned east and north)"
  /// An ensemble statistic's members, each read alone on the same surface (the readout gives
  /// every member's value under the cursor): the member (GRIB `number`, netCDF the ensemble
  /// coordinate's value or index) and its field. Empty without a statistic.
  std::vector<std::pair<long, volume::SurfaceField>> members;
};

/// Checks the description (ranges, a fill or contours to draw, not both a member and an
/// ensemble statistic); errors start with `where`.
Status validateSurfaceLayer(const SurfaceLayerDescription& d, const std::string& where);

/// Whether two descriptions read the same data (file, variable, time, member or statistic,
/// pressure or level, wind, datum): a change of anything else (colours, range, opacity,
/// contours) redraws what is loaded without reading again.
bool sameSurfaceData(const SurfaceLayerDescription& a, const SurfaceLayerDescription& b);

/// Reads the variable (the time, member or statistic asked) and makes its field
/// (volume::surfaceFieldOf), the wind when asked, and with a statistic each member's field.
/// Errors name the file.
Result<SurfaceData> readSurfaceData(const SurfaceLayerDescription& d);

/// The u and v variables of `wind` ("auto" or "U,V") in `path`. Errors: none found (naming what
/// to give), a malformed pair.
Result<std::pair<std::string, std::string>> windVariables(const std::string& path, const std::string& wind,
                                                          bool isobaric);

}  // namespace atmoglobe::engine
