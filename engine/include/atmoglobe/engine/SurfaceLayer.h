#pragma once
// A 2-D field of a forecast grid drawn on the globe (scene "surfaces", CLI --surface): what to
// read (file, variable, time, member or ensemble statistic, a pressure level for a 3-D
// variable), the fill (colour table, range, opacity) and contour lines (interval or values,
// labelled). GL-free: SurfaceFieldGL.h draws it; volume/SurfaceField.h is its field and CPU
// reference.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/SurfaceField.h>
#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::engine {

struct SurfaceLayerDescription {
  std::string path;                   ///< resolved (absolute or relative to the working directory)
  std::string variable;               ///< "" : the file's default variable
  std::string time;                   ///< an index ("0") or an ISO 8601 UTC time; "": the first
  int member = -1;                    ///< GRIB `number` (-1: the first)
  std::string ensemble;               ///< "" or mean|spread|min|max|prob:OPV (volume::parseEnsembleStatistic)
  std::optional<double> pressureHpa;  ///< a 3-D variable's isobaric surface
  std::string colors = "auto";        ///< as a grid layer's (volume::transferForField)
  std::optional<glm::dvec2> valueRange;
  double opacity = 0.75;  ///< of the fill, 0..1
  bool fill = true;
  std::optional<double> contourInterval;  ///< contour lines every this many field units
  std::vector<double> contourValues;      ///< or at these values
  glm::vec3 contourColor{0.05f, 0.05f, 0.05f};
  float contourWidthPx = 1.5f;
  bool contourLabels = true;
  bool useGeoid = true;
};

/// Checks the description (ranges, a fill or contours to draw, not both a member and an
/// ensemble statistic); errors start with `where`.
Status validateSurfaceLayer(const SurfaceLayerDescription& d, const std::string& where);

/// Reads the variable (the time, member or statistic asked) and makes its field
/// (volume::surfaceFieldOf). Errors name the file.
Result<volume::SurfaceField> readSurfaceField(const SurfaceLayerDescription& d);

}  // namespace atmoglobe::engine
