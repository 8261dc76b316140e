// A grid's 2-D field on the globe (SurfaceField.h).
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/SliceSource.h>
#include <atmoglobe/volume/SurfaceField.h>
#include <atmoglobe/volume/VerticalCoordinate.h>

#include <cmath>
#include <cstdio>
#include <limits>

namespace atmoglobe::volume {

Result<std::vector<float>> isobaricColumnValues(const GridVolume& grid, double pressurePa, bool nearestLevel) {
  const std::size_t columns = grid.nx * grid.ny;
  std::vector<float> out(columns, std::numeric_limits<float>::quiet_NaN());
  if (!grid.pressurePa.empty()) {
    // Terrain-following levels: each column's own pressures. Where the surface lies below the
    // column's lowest level (under ground) or above its top, the column has no value there.
    if (grid.pressurePa.size() != grid.values.size())
      return makeError(grid.path + ": '" + grid.variable + "': " + std::to_string(grid.pressurePa.size()) +
                       " pressures for " + std::to_string(grid.values.size()) + " values");
    if (!(pressurePa > 0.0) || !std::isfinite(pressurePa))
      return makeError(grid.path + ": the pressure of an isobaric surface must be positive");
    const double lnP = std::log(pressurePa);
    bool any = false;
    double lowest = std::numeric_limits<double>::infinity(), highest = 0.0;
    for (std::size_t c = 0; c < columns; ++c) {
      for (std::size_t k = 0; k + 1 < grid.nz; ++k) {
        const double a = grid.pressurePa[k * columns + c], b = grid.pressurePa[(k + 1) * columns + c];
        if (k == 0 && a > highest) highest = a;
        if (k + 2 == grid.nz && b < lowest) lowest = b;
        if (!(a > 0.0 && b > 0.0) || !((pressurePa <= a && pressurePa >= b) || (pressurePa >= a && pressurePa <= b)))
          continue;
        double f = a == b ? 0.0 : (std::log(a) - lnP) / (std::log(a) - std::log(b));
        if (nearestLevel) f = f < 0.5 ? 0.0 : 1.0;
        const double lower = grid.values[k * columns + c], upper = grid.values[(k + 1) * columns + c];
        const double v = f <= 0.0 ? lower : f >= 1.0 ? upper : (1.0 - f) * lower + f * upper;
        if (std::isfinite(v)) out[c] = static_cast<float>(v);
        any = true;
        break;
      }
    }
    if (!any) {
      char text[256];
      std::snprintf(text, sizeof text,
                    "%g hPa is outside the levels of every column: their pressures run from %g hPa "
                    "(the highest at the bottom) to %g hPa (the lowest at the top)",
                    pressurePa / 100.0, highest / 100.0, lowest / 100.0);
      return makeError(grid.path + ": '" + grid.variable + "': " + text);
    }
    return out;
  }
  auto bracket = pressureBracket(grid, pressurePa);
  if (!bracket) return bracket.forwardError();
  auto [k, f] = *bracket;
  if (nearestLevel) f = f < 0.5 ? 0.0 : 1.0;
  for (std::size_t c = 0; c < columns; ++c) {
    const double lower = grid.values[k * columns + c];
    const double upper = f > 0.0 ? static_cast<double>(grid.values[(k + 1) * columns + c]) : lower;
    const double v = f >= 1.0 ? upper : (1.0 - f) * lower + f * upper;
    if (std::isfinite(v)) out[c] = static_cast<float>(v);
  }
  return out;
}

Result<SurfaceField> surfaceFieldOf(GridVolume grid, std::optional<double> pressurePa,
                                    std::optional<std::size_t> level) {
  const std::string what = grid.path + ": '" + grid.variable + "'";
  if (grid.reduced()) return makeError(what + " is on a reduced grid: not drawn as a surface field yet");
  if (grid.nx < 2 || grid.ny < 2) return makeError(what + ": a surface field needs at least 2 x 2 grid points");
  SurfaceField s;
  s.pressurePa = pressurePa;
  std::string name = grid.variable;
  if (const auto slash = name.rfind('/'); slash != std::string::npos) name = name.substr(slash + 1);
  // A GRIB variable's level type says nothing once the surface is named by its pressure.
  if (const auto colon = name.find(':'); pressurePa && colon != std::string::npos) name = name.substr(0, colon);
  const std::size_t columns = grid.nx * grid.ny;
  if (pressurePa && level) return makeError(what + ": give a pressure or a level, not both");
  if (level) {
    if (*level >= grid.nz)
      return makeError(what + ": level " + std::to_string(*level) + " asked, it has " + std::to_string(grid.nz) +
                       " (0 = the lowest)");
    grid.values = std::vector<float>(grid.values.begin() + static_cast<std::ptrdiff_t>(*level * columns),
                                     grid.values.begin() + static_cast<std::ptrdiff_t>((*level + 1) * columns));
    name += " at level " + std::to_string(*level);
  } else if (pressurePa) {
    auto values = isobaricColumnValues(grid, *pressurePa);
    if (!values) return values.forwardError();
    grid.values = std::move(*values);
    char at[64];
    std::snprintf(at, sizeof at, " at %g hPa", *pressurePa / 100.0);
    name += at;
  } else if (grid.nz != 1) {
    return makeError(what + " has " + std::to_string(grid.nz) +
                     " levels: give a pressure level (--surface-pressure-hpa, scene \"pressure_hpa\"), a level "
                     "(--surface-level) or a 2-D variable");
  } else {
    grid.values.resize(columns);
  }
  // Geopotential is shown as forecasters read it, as `slice` does: geopotential height in
  // decametres (500 hPa contours every 6 dam).
  if (const auto toSi = geopotentialUnitToSi(grid.units)) {
    for (float& v : grid.values) v = static_cast<float>(v * *toSi / kStandardGravity / 10.0);
    grid.units = "dam";
    name += " (geopotential height)";
  }
  grid.nz = 1;
  grid.heightAboveEllipsoidMeters.assign(columns, 0.0f);
  grid.levelValues.clear();
  setValueRange(grid);
  if (std::isnan(grid.valueMin))
    return makeError(what + (pressurePa ? " has no value on that surface" : " has no value"));
  s.name = std::move(name);
  s.grid = std::move(grid);
  return s;
}

SurfaceSampler::SurfaceSampler(const SurfaceField& field)
    : field_(field), sampler_(std::make_unique<GridSampler>(field.grid)) {}

double SurfaceSampler::valueAt(double latDeg, double lonDeg) const {
  const auto ij = sampler_->horizontalIndex(latDeg, lonDeg);
  if (!ij) return std::numeric_limits<double>::quiet_NaN();
  const GridColumns c = sampler_->columnsAt(*ij);
  if (c.count == 0) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (int n = 0; n < c.count; ++n) {
    if (c.weight[n] == 0.0) continue;
    const double v = sampler_->columnValue(c.column[n], 0);
    if (!std::isfinite(v)) return std::numeric_limits<double>::quiet_NaN();
    sum += c.weight[n] * v;
  }
  return sum;
}

bool surfaceValueShows(const ColorTable& table, double value) {
  return std::isfinite(value) && !table.empty() &&
         value * table.scale() + table.offset() >= table.stops().front().value;
}

VolumeImage renderSurfaceReference(const SurfaceSampler& sampler, const ColorTable& table, double opacity,
                                   const RenderCamera& camera) {
  VolumeImage image;
  image.widthPx = camera.widthPx;
  image.heightPx = camera.heightPx;
  image.rgbaPremultiplied.assign(static_cast<std::size_t>(camera.widthPx) * static_cast<std::size_t>(camera.heightPx),
                                 glm::dvec4(0.0));
  for (int y = 0; y < camera.heightPx; ++y)
    for (int x = 0; x < camera.widthPx; ++x) {
      const glm::dvec3 dir = pixelRayDirection(camera, x + 0.5, y + 0.5);
      const auto hit = globe::intersectRayEllipsoid(camera.eyeEcef, dir);
      if (!hit) continue;
      const globe::Geodetic g = globe::ecefToGeodetic(*hit);
      const double v = sampler.valueAt(g.latDeg, g.lonDeg);
      if (!surfaceValueShows(table, v)) continue;
      const Rgba8 c = table.map(static_cast<float>(v));
      image.rgbaPremultiplied[static_cast<std::size_t>(y) * static_cast<std::size_t>(camera.widthPx) +
                              static_cast<std::size_t>(x)] =
          glm::dvec4(c.r / 255.0 * opacity, c.g / 255.0 * opacity, c.b / 255.0 * opacity, opacity);
    }
  return image;
}

}  // namespace atmoglobe::volume
