// The forecast grid's CPU sampler (GridSampler.h).
#include <atmoglobe/volume/GridSampler.h>

#include <atmoglobe/globe/Ellipsoid.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

namespace atmoglobe::volume {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// x taken modulo 360 into [origin, origin + 360).
double wrapFrom(double x, double origin) {
  double d = std::fmod(x - origin, 360.0);
  if (d < 0.0) d += 360.0;
  return origin + d;
}

// Fractional index of x in the increasing array a (size >= 2), x within [a.front(), a.back()].
double fractionalIndex(const std::vector<double>& a, std::size_t n, double x) {
  const auto it = std::upper_bound(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(n), x);
  std::size_t k = it == a.begin() ? 0 : static_cast<std::size_t>(it - a.begin()) - 1;
  k = std::min(k, n - 2);
  return static_cast<double>(k) + (x - a[k]) / (a[k + 1] - a[k]);
}

// The unit vector of a latitude/longitude taken as spherical angles (the chart's own sphere).
glm::dvec3 unitVector(double latDeg, double lonDeg) {
  const double la = glm::radians(latDeg), lo = glm::radians(lonDeg);
  return {std::cos(la) * std::cos(lo), std::cos(la) * std::sin(lo), std::sin(la)};
}

}  // namespace

glm::dvec2 GridSampler::toChart(double latDeg, double lonDeg) const {
  const glm::dvec3 q = chart_ * unitVector(latDeg, lonDeg);
  return {glm::degrees(std::atan2(q.y, q.x)), glm::degrees(std::asin(std::clamp(q.z, -1.0, 1.0)))};
}

GridSampler::GridSampler(const GridVolume& grid) : grid_(grid) {
  const std::size_t columns = grid.nx * grid.ny;
  minHeight_ = std::numeric_limits<double>::infinity();
  maxHeight_ = -std::numeric_limits<double>::infinity();
  for (float h : grid.heightAboveEllipsoidMeters) {
    if (!std::isfinite(h)) continue;
    minHeight_ = std::min(minHeight_, double(h));
    maxHeight_ = std::max(maxHeight_, double(h));
  }
  if (!(minHeight_ <= maxHeight_)) minHeight_ = maxHeight_ = 0.0;

  if (grid.reduced()) {
    west_ = grid.reducedWestDeg();
    step_ = grid.reducedSpacingDeg();
  }

  // Global grids close their polar caps with the mean of the end rows (a reduced grid's: of the
  // row's own points).
  poleCaps_ = !grid.curvilinear && grid.wrapsLongitude && grid.ny >= 1;
  if (poleCaps_) {
    for (auto [row, height, value] : {std::tuple{grid.ny - 1, &northHeight_, &northValue_},
                                      std::tuple{std::size_t{0}, &southHeight_, &southValue_}}) {
      height->assign(grid.nz, 0.0);
      value->assign(grid.nz, 0.0f);
      const std::size_t n = grid.rowLength(row);
      for (std::size_t k = 0; k < grid.nz; ++k) {
        double hs = 0.0, vs = 0.0;
        bool missing = false;
        for (std::size_t i = 0; i < n; ++i) {
          hs += grid.heightMeters(k, row, i);
          const float v = grid.value(k, row, i);
          missing = missing || !std::isfinite(v);
          vs += v;
        }
        (*height)[k] = hs / static_cast<double>(n);
        (*value)[k] = missing ? std::numeric_limits<float>::quiet_NaN()
                              : static_cast<float>(vs / static_cast<double>(n));
      }
    }
  }

  // Curvilinear: the bin index over the cells' corner boxes, in the chart (see GridSampler.h).
  if (grid.curvilinear && grid.nx >= 2 && grid.ny >= 2) {
    const double latMin0 = *std::min_element(grid.latDeg.begin(), grid.latDeg.end());
    const double latMax0 = *std::max_element(grid.latDeg.begin(), grid.latDeg.end());
    const double lonMin0 = *std::min_element(grid.lonDeg.begin(), grid.lonDeg.end());
    const double lonMax0 = *std::max_element(grid.lonDeg.begin(), grid.lonDeg.end());
    if (latMax0 > 80.0 || latMin0 < -80.0 || lonMax0 - lonMin0 > 180.0) {
      // The grid's mean direction becomes the chart's (0, 0); its "north" the meridian there.
      glm::dvec3 mean(0.0);
      for (std::size_t p = 0; p < grid.lonDeg.size(); ++p) mean += unitVector(grid.latDeg[p], grid.lonDeg[p]);
      const glm::dvec3 e1 = glm::length(mean) > 1e-9 ? glm::normalize(mean) : glm::dvec3(1, 0, 0);
      glm::dvec3 up = glm::dvec3(0, 0, 1) - e1.z * e1;
      if (glm::length(up) < 1e-6) up = glm::dvec3(1, 0, 0) - e1.x * e1;  // centred on a pole
      const glm::dvec3 e3 = glm::normalize(up), e2 = glm::cross(e3, e1);
      chart_ = glm::transpose(glm::dmat3(e1, e2, e3));  // rows e1, e2, e3
      charted_ = true;
      chartLat_.resize(grid.latDeg.size());
      chartLon_.resize(grid.lonDeg.size());
      for (std::size_t p = 0; p < grid.lonDeg.size(); ++p) {
        const glm::dvec2 c = toChart(grid.latDeg[p], grid.lonDeg[p]);
        chartLat_[p] = c.y;
        chartLon_[p] = c.x;
      }
    }
    const std::vector<double>& lats = charted_ ? chartLat_ : grid.latDeg;
    const std::vector<double>& lons = charted_ ? chartLon_ : grid.lonDeg;
    auto latAt = [&](std::size_t j, std::size_t i) { return lats[j * grid.nx + i]; };
    auto lonAt = [&](std::size_t j, std::size_t i) { return lons[j * grid.nx + i]; };
    lonMin_ = *std::min_element(lons.begin(), lons.end());
    const double lonMax = *std::max_element(lons.begin(), lons.end());
    const double latMin = *std::min_element(lats.begin(), lats.end());
    const double latMax = *std::max_element(lats.begin(), lats.end());
    const std::size_t cells = (grid.nx - 1) * (grid.ny - 1);
    const int side = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(cells)) / 2.0), 1, 256);
    binsLat_ = binsLon_ = side;
    latMinBin_ = latMin;
    lonMinBin_ = lonMin_;
    binLatDeg_ = std::max(1e-9, (latMax - latMin) / side);
    binLonDeg_ = std::max(1e-9, (lonMax - lonMin_) / side);
    bins_.assign(static_cast<std::size_t>(side) * static_cast<std::size_t>(side), {});
    for (std::size_t j = 0; j + 1 < grid.ny; ++j)
      for (std::size_t i = 0; i + 1 < grid.nx; ++i) {
        double la0 = 1e300, la1 = -1e300, lo0 = 1e300, lo1 = -1e300;
        for (std::size_t dj = 0; dj < 2; ++dj)
          for (std::size_t di = 0; di < 2; ++di) {
            la0 = std::min(la0, latAt(j + dj, i + di));
            la1 = std::max(la1, latAt(j + dj, i + di));
            lo0 = std::min(lo0, lonAt(j + dj, i + di));
            lo1 = std::max(lo1, lonAt(j + dj, i + di));
          }
        auto bin = [](double x, double origin, double size, int n) {
          return std::clamp(static_cast<int>(std::floor((x - origin) / size)), 0, n - 1);
        };
        for (int b = bin(la0, latMinBin_, binLatDeg_, binsLat_); b <= bin(la1, latMinBin_, binLatDeg_, binsLat_); ++b)
          for (int c = bin(lo0, lonMinBin_, binLonDeg_, binsLon_); c <= bin(lo1, lonMinBin_, binLonDeg_, binsLon_); ++c)
            bins_[static_cast<std::size_t>(b) * static_cast<std::size_t>(binsLon_) + static_cast<std::size_t>(c)]
                .push_back(static_cast<std::uint32_t>(j * (grid.nx - 1) + i));
      }
  }

  // Bounding sphere: the whole atmosphere for global grids, else sampled columns at their
  // lowest and highest level, widened by the sagitta between samples (the top surface bulges
  // outwards between them) and 10 m.
  const double lonSpan = grid.reduced() ? grid.reducedEastDeg() - grid.reducedWestDeg()
                         : grid.nx >= 2 ? grid.lonDeg.back() - grid.lonDeg.front()
                                        : 0.0;
  const bool global = grid.wrapsLongitude || columns == 0 || (!grid.curvilinear && lonSpan >= 180.0) ||
                      (!grid.curvilinear && grid.ny >= 2 && grid.latDeg.back() - grid.latDeg.front() >= 90.0);
  if (global) {
    sphere_ = {glm::dvec3(0.0), globe::kWgs84A + std::max(0.0, maxHeight_) + 1.0};
  } else if (grid.reduced()) {
    // Sampled points of sampled rows (each row by its own length), the spacing between
    // neighbours along a row and between rows at one longitude.
    const std::size_t sy = std::max<std::size_t>(1, grid.ny / 48);
    std::vector<std::size_t> js;
    for (std::size_t j = 0; j < grid.ny; j += sy) js.push_back(j);
    if (js.back() != grid.ny - 1) js.push_back(grid.ny - 1);
    std::vector<glm::dvec3> pts;
    glm::dvec3 lo(1e300), hi(-1e300);
    double spacing = 0.0;
    for (std::size_t b = 0; b < js.size(); ++b) {
      const std::size_t j = js[b], n = grid.rowLength(j), sx = std::max<std::size_t>(1, n / 48);
      std::vector<std::size_t> is;
      for (std::size_t i = 0; i < n; i += sx) is.push_back(i);
      if (is.back() != n - 1) is.push_back(n - 1);
      for (std::size_t a = 0; a < is.size(); ++a) {
        const double lat = grid.latDeg[j], lon = grid.lonDegAt(j, is[a]);
        const glm::dvec3 base = globe::geodeticToEcef({lat, lon, minHeight_});
        const glm::dvec3 top = globe::geodeticToEcef({lat, lon, maxHeight_});
        for (const glm::dvec3& p : {base, top}) {
          lo = glm::min(lo, p);
          hi = glm::max(hi, p);
          pts.push_back(p);
        }
        if (a > 0)
          spacing = std::max(spacing,
                             glm::length(top - globe::geodeticToEcef({lat, grid.lonDegAt(j, is[a - 1]), maxHeight_})));
        if (b > 0)
          spacing =
              std::max(spacing, glm::length(top - globe::geodeticToEcef({grid.latDeg[js[b - 1]], lon, maxHeight_})));
      }
    }
    const glm::dvec3 centre = 0.5 * (lo + hi);
    double radius = 0.0;
    for (const glm::dvec3& p : pts) radius = std::max(radius, glm::length(p - centre));
    sphere_ = {centre, radius + spacing * spacing / (8.0 * 6.35e6) + 10.0};
  } else {
    const std::size_t sx = std::max<std::size_t>(1, grid.nx / 48), sy = std::max<std::size_t>(1, grid.ny / 48);
    std::vector<std::size_t> is, js;
    for (std::size_t i = 0; i < grid.nx; i += sx) is.push_back(i);
    if (is.back() != grid.nx - 1) is.push_back(grid.nx - 1);
    for (std::size_t j = 0; j < grid.ny; j += sy) js.push_back(j);
    if (js.back() != grid.ny - 1) js.push_back(grid.ny - 1);
    std::vector<glm::dvec3> pts;
    glm::dvec3 lo(1e300), hi(-1e300);
    double spacing = 0.0;
    for (std::size_t b = 0; b < js.size(); ++b)
      for (std::size_t a = 0; a < is.size(); ++a) {
        const double lat = grid.latDegAt(js[b], is[a]), lon = grid.lonDegAt(js[b], is[a]);
        const glm::dvec3 base = globe::geodeticToEcef({lat, lon, minHeight_});
        const glm::dvec3 top = globe::geodeticToEcef({lat, lon, maxHeight_});
        for (const glm::dvec3& p : {base, top}) {
          lo = glm::min(lo, p);
          hi = glm::max(hi, p);
          pts.push_back(p);
        }
        if (a > 0)
          spacing = std::max(spacing,
                             glm::length(top - globe::geodeticToEcef({grid.latDegAt(js[b], is[a - 1]),
                                                                      grid.lonDegAt(js[b], is[a - 1]), maxHeight_})));
        if (b > 0)
          spacing = std::max(spacing,
                             glm::length(top - globe::geodeticToEcef({grid.latDegAt(js[b - 1], is[a]),
                                                                      grid.lonDegAt(js[b - 1], is[a]), maxHeight_})));
      }
    const glm::dvec3 centre = 0.5 * (lo + hi);
    double radius = 0.0;
    for (const glm::dvec3& p : pts) radius = std::max(radius, glm::length(p - centre));
    sphere_ = {centre, radius + spacing * spacing / (8.0 * 6.35e6) + 10.0};
  }

  // The step rule's cell scale (StepRule.h): mean level heights over at most ~65,000 columns
  // (every column, or every s-th row and column), and the distance from the middle grid point to
  // its neighbours along the row and the column.
  if (grid.nz > 0 && grid.nx > 0 && grid.ny > 0) {
    const std::size_t stride = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(columns) / 65536.0))));
    std::vector<double> mean(grid.nz, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t k = 0; k < grid.nz; ++k) {
      double sum = 0.0;
      std::size_t n = 0;
      for (std::size_t j = 0; j < grid.ny; j += stride)
        for (std::size_t i = 0; i < grid.rowLength(j); i += stride) {
          const float h = grid.heightMeters(k, j, i);
          if (!std::isfinite(h)) continue;
          sum += h;
          ++n;
        }
      if (n > 0) mean[k] = sum / static_cast<double>(n);
    }
    if (grid.nz >= 2 && mean.front() > mean.back()) std::reverse(mean.begin(), mean.end());
    double spacing = std::numeric_limits<double>::infinity();
    const std::size_t j = grid.ny / 2, i = grid.rowLength(j) / 2;
    auto distance = [&](std::size_t j2, std::size_t i2) {
      const double d =
          globe::geodesicInverse(grid.latDegAt(j, i), grid.lonDegAt(j, i), grid.latDegAt(j2, i2), grid.lonDegAt(j2, i2))
              .distanceMeters;
      if (d > 0.0) spacing = std::min(spacing, d);
    };
    if (i + 1 < grid.rowLength(j)) distance(j, i + 1);
    if (j + 1 < grid.ny) distance(j + 1, std::min(i, grid.rowLength(j + 1) - 1));
    cellScale_ = cellScaleFromLevels(mean, minHeight_, maxHeight_, std::isfinite(spacing) ? spacing : 0.0);
  }
}

double GridSampler::cellCrossingMeters(const glm::dvec3& ecef, const glm::dvec3& unitDirEcef) const {
  return volume::cellCrossingMeters(cellScale_, ecef, unitDirEcef);
}

RayInterval GridSampler::rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const {
  const RayInterval a = raySphereInterval(eyeEcef, unitDirEcef, sphere_.centreEcef, sphere_.radiusMeters);
  // The shell's outside: the ellipsoid raised by the top height lies inside this sphere.
  const RayInterval b =
      raySphereInterval(eyeEcef, unitDirEcef, glm::dvec3(0.0), globe::kWgs84A + std::max(0.0, maxHeight_) + 1.0);
  if (a.empty() || b.empty()) return {};
  return {std::max(a.tEnterMeters, b.tEnterMeters), std::min(a.tExitMeters, b.tExitMeters)};
}

ValueRange GridSampler::valueRange() const {
  if (!(grid_.valueMin <= grid_.valueMax)) return {0.0, 1.0};
  return {grid_.valueMin, grid_.valueMax};
}

std::string GridSampler::description() const {
  std::ostringstream s;
  s << grid_.variable << " from " << grid_.path << " (" << grid_.nx << " x " << grid_.ny << " x " << grid_.nz
    << (grid_.curvilinear ? ", curvilinear" : "") << (grid_.reduced() ? ", reduced" : "");
  if (!grid_.validTime.empty()) s << ", " << grid_.validTime;
  s << ")";
  return s.str();
}

std::optional<glm::dvec2> GridSampler::curvilinearIndex(double latDeg, double lonDeg) const {
  if (bins_.empty()) return std::nullopt;
  if (charted_) {
    const glm::dvec2 c = toChart(latDeg, lonDeg);
    latDeg = c.y;
    lonDeg = c.x;
  }
  const std::vector<double>& lats = charted_ ? chartLat_ : grid_.latDeg;
  const std::vector<double>& lons = charted_ ? chartLon_ : grid_.lonDeg;
  const std::size_t nx = grid_.nx;
  auto at = [&](std::size_t j, std::size_t i) { return glm::dvec2(lons[j * nx + i], lats[j * nx + i]); };
  const double lon = wrapFrom(lonDeg, lonMin_);
  const int b = static_cast<int>(std::floor((latDeg - latMinBin_) / binLatDeg_));
  const int c = static_cast<int>(std::floor((lon - lonMinBin_) / binLonDeg_));
  // A point on the far edge belongs to the last bin.
  const int bb = b == binsLat_ && latDeg <= latMinBin_ + binsLat_ * binLatDeg_ ? b - 1 : b;
  const int cc = c == binsLon_ && lon <= lonMinBin_ + binsLon_ * binLonDeg_ ? c - 1 : c;
  if (bb < 0 || bb >= binsLat_ || cc < 0 || cc >= binsLon_) return std::nullopt;
  const std::size_t nx1 = grid_.nx - 1;
  for (std::uint32_t cell :
       bins_[static_cast<std::size_t>(bb) * static_cast<std::size_t>(binsLon_) + static_cast<std::size_t>(cc)]) {
    const std::size_t j = cell / nx1, i = cell % nx1;
    const glm::dvec2 p00 = at(j, i), p10 = at(j, i + 1), p01 = at(j + 1, i), p11 = at(j + 1, i + 1);
    const glm::dvec2 target(lon, latDeg);
    // Newton on P(u, v) = target, P bilinear in the cell.
    double u = 0.5, v = 0.5;
    bool converged = false;
    for (int it = 0; it < 30; ++it) {
      const glm::dvec2 p = (1 - u) * (1 - v) * p00 + u * (1 - v) * p10 + (1 - u) * v * p01 + u * v * p11;
      const glm::dvec2 du = (1 - v) * (p10 - p00) + v * (p11 - p01);
      const glm::dvec2 dv = (1 - u) * (p01 - p00) + u * (p11 - p10);
      const double det = du.x * dv.y - du.y * dv.x;
      if (!(std::abs(det) > 0.0)) break;
      const glm::dvec2 r = target - p;
      const double su = (r.x * dv.y - r.y * dv.x) / det, sv = (du.x * r.y - du.y * r.x) / det;
      u += su;
      v += sv;
      if (std::abs(su) < 1e-12 && std::abs(sv) < 1e-12) {
        converged = true;
        break;
      }
      if (std::abs(u) > 10.0 || std::abs(v) > 10.0) break;  // far outside this cell
    }
    constexpr double kEdge = 1e-10;  // a point on a shared edge may land in either cell
    if (converged && u >= -kEdge && u <= 1.0 + kEdge && v >= -kEdge && v <= 1.0 + kEdge)
      return glm::dvec2(static_cast<double>(i) + std::clamp(u, 0.0, 1.0),
                        static_cast<double>(j) + std::clamp(v, 0.0, 1.0));
  }
  return std::nullopt;
}

std::optional<double> GridSampler::rowIndex(double latDeg) const {
  const GridVolume& g = grid_;
  if (g.curvilinear || g.ny == 0 || !std::isfinite(latDeg)) return std::nullopt;
  const double lat0 = g.latDeg[0], latN = g.latDeg[g.ny - 1];
  if (latDeg < lat0) {
    if (!poleCaps_ || lat0 <= -90.0) return std::nullopt;
    return -(lat0 - latDeg) / (lat0 + 90.0);
  }
  if (latDeg > latN) {
    if (!poleCaps_ || latN >= 90.0) return std::nullopt;
    return static_cast<double>(g.ny - 1) + (latDeg - latN) / (90.0 - latN);
  }
  return g.ny >= 2 ? fractionalIndex(g.latDeg, g.ny, latDeg) : 0.0;
}

std::optional<double> GridSampler::rowColumn(std::size_t j, double lonDeg) const {
  const double first = grid_.rowFirstLonDeg[j], step = grid_.rowSpacingDeg[j];
  const auto n = static_cast<double>(grid_.rowLengthPoints[j]);
  double x = (wrapFrom(lonDeg, first) - first) / step;
  // A grid point's longitude, after a round trip through the reference axis, a hair off.
  if (const double r = std::round(x); std::abs(x - r) < 1e-9) x = r;
  if (grid_.wrapsLongitude) return x >= n ? x - n : x;  // x in [0, n): across the seam past n - 1
  if (x <= n - 1.0) return x;
  return std::nullopt;
}

std::array<GridSampler::RowWeight, 2> GridSampler::rowsAt(double j) const {
  const GridVolume& g = grid_;
  if (j < 0.0) return {RowWeight{0, 1.0 + j}, RowWeight{GridColumns::kSouthPole, -j}};
  if (j > static_cast<double>(g.ny - 1)) {
    const double t = j - static_cast<double>(g.ny - 1);
    return {RowWeight{static_cast<int>(g.ny - 1), 1.0 - t}, RowWeight{GridColumns::kNorthPole, t}};
  }
  std::size_t j0 = static_cast<std::size_t>(std::floor(j));
  double fj = j - static_cast<double>(j0);
  if (j0 >= g.ny - 1) {
    j0 = g.ny - 1;
    fj = 0.0;
  }
  return {RowWeight{static_cast<int>(j0), 1.0 - fj}, RowWeight{static_cast<int>(std::min(j0 + 1, g.ny - 1)), fj}};
}

std::optional<glm::dvec2> GridSampler::horizontalIndex(double latDeg, double lonDeg) const {
  const GridVolume& g = grid_;
  if (g.nx == 0 || g.ny == 0 || !std::isfinite(latDeg) || !std::isfinite(lonDeg)) return std::nullopt;
  if (g.curvilinear) return curvilinearIndex(latDeg, lonDeg);
  if (g.reduced()) {
    const std::optional<double> j = rowIndex(latDeg);
    if (!j) return std::nullopt;
    for (const RowWeight& r : rowsAt(*j))
      if (r.row >= 0 && r.weight > 0.0 && !rowColumn(static_cast<std::size_t>(r.row), lonDeg)) return std::nullopt;
    return glm::dvec2((wrapFrom(lonDeg, west_) - west_) / step_, *j);
  }
  // Columns.
  double i = 0.0;
  const double x = wrapFrom(lonDeg, g.lonDeg[0]);
  if (g.nx == 1) {
    if (!g.wrapsLongitude && x != g.lonDeg[0]) return std::nullopt;
  } else if (x <= g.lonDeg[g.nx - 1]) {
    i = fractionalIndex(g.lonDeg, g.nx, x);
  } else if (g.wrapsLongitude) {
    i = static_cast<double>(g.nx - 1) + (x - g.lonDeg[g.nx - 1]) / (g.lonDeg[0] + 360.0 - g.lonDeg[g.nx - 1]);
  } else {
    return std::nullopt;
  }
  // Rows (latitudes ascending), with the polar caps of global grids.
  double j = 0.0;
  const double lat0 = g.latDeg[0], latN = g.latDeg[g.ny - 1];
  if (latDeg < lat0) {
    if (!poleCaps_ || lat0 <= -90.0) return std::nullopt;
    j = -(lat0 - latDeg) / (lat0 + 90.0);
  } else if (latDeg > latN) {
    if (!poleCaps_ || latN >= 90.0) return std::nullopt;
    j = static_cast<double>(g.ny - 1) + (latDeg - latN) / (90.0 - latN);
  } else if (g.ny >= 2) {
    j = fractionalIndex(g.latDeg, g.ny, latDeg);
  }
  return glm::dvec2(i, j);
}

GridColumns GridSampler::columnsAt(const glm::dvec2& ij) const {
  const GridVolume& g = grid_;
  if (g.reduced()) {
    // Each row by its own column fraction of the longitude, then linear in latitude.
    const double lon = west_ + ij.x * step_;
    GridColumns out;
    auto add = [&](int column, double w) {
      if (w <= 0.0) return;
      for (int k = 0; k < out.count; ++k)
        if (out.column[k] == column) {
          out.weight[k] += w;
          return;
        }
      out.column[out.count] = column;
      out.weight[out.count] = w;
      ++out.count;
    };
    const std::array<RowWeight, 2> rows = rowsAt(ij.y);
    for (const RowWeight& r : rows) {
      if (r.row < 0) {
        add(r.row, r.weight);
        continue;
      }
      const auto row = static_cast<std::size_t>(r.row);
      const std::size_t n = g.rowLengthPoints[row];
      // Outside the row (a fractional index not from horizontalIndex): its nearer end.
      const double x = rowColumn(row, lon).value_or(
          wrapFrom(lon, g.rowFirstLonDeg[row]) - g.rowFirstLonDeg[row] > 180.0 ? 0.0 : static_cast<double>(n - 1));
      std::size_t i0 = static_cast<std::size_t>(std::max(0.0, std::floor(x)));
      double fi = x - static_cast<double>(i0);
      std::size_t i1 = i0 + 1;
      if (i0 >= n - 1) {
        if (g.wrapsLongitude && i0 == n - 1 && fi > 0.0) {
          i1 = 0;  // across the seam
        } else {
          i0 = i1 = n - 1;
          fi = 0.0;
        }
      }
      const int base = r.row * static_cast<int>(g.nx);
      add(base + static_cast<int>(i0), r.weight * (1.0 - fi));
      add(base + static_cast<int>(i1), r.weight * fi);
    }
    if (out.count == 0) {  // every weight zero cannot happen for t in [0, 1]; keep one column
      out.column[0] = rows[0].row < 0 ? rows[0].row : rows[0].row * static_cast<int>(g.nx);
      out.weight[0] = 1.0;
      out.count = 1;
    }
    return out;
  }
  // Columns and their weights along i.
  std::size_t i0 = static_cast<std::size_t>(std::max(0.0, std::floor(ij.x)));
  double fi = ij.x - static_cast<double>(i0);
  std::size_t i1 = i0 + 1;
  if (i0 >= g.nx - 1) {
    if (g.wrapsLongitude && !g.curvilinear && i0 == g.nx - 1 && fi > 0.0) {
      i1 = 0;  // across the seam
    } else {
      i0 = i1 = g.nx - 1;
      fi = 0.0;
    }
  }
  // Rows (or a pole) and their weights along j.
  struct Row {
    int row;  // >= 0 a row, else a pole
    double weight;
  };
  std::array<Row, 2> rows{};
  if (ij.y < 0.0) {
    const double t = -ij.y;
    rows = {Row{0, 1.0 - t}, Row{GridColumns::kSouthPole, t}};
  } else if (ij.y > static_cast<double>(g.ny - 1)) {
    const double t = ij.y - static_cast<double>(g.ny - 1);
    rows = {Row{static_cast<int>(g.ny - 1), 1.0 - t}, Row{GridColumns::kNorthPole, t}};
  } else {
    std::size_t j0 = static_cast<std::size_t>(std::floor(ij.y));
    double fj = ij.y - static_cast<double>(j0);
    if (j0 >= g.ny - 1) {
      j0 = g.ny - 1;
      fj = 0.0;
    }
    rows = {Row{static_cast<int>(j0), 1.0 - fj}, Row{static_cast<int>(std::min(j0 + 1, g.ny - 1)), fj}};
  }
  GridColumns out;
  auto add = [&](int column, double w) {
    if (w <= 0.0) return;
    for (int k = 0; k < out.count; ++k)
      if (out.column[k] == column) {
        out.weight[k] += w;
        return;
      }
    out.column[out.count] = column;
    out.weight[out.count] = w;
    ++out.count;
  };
  for (const Row& r : rows) {
    if (r.row < 0) {
      add(r.row, r.weight);
      continue;
    }
    const int base = r.row * static_cast<int>(g.nx);
    add(base + static_cast<int>(i0), r.weight * (1.0 - fi));
    add(base + static_cast<int>(i1), r.weight * fi);
  }
  if (out.count == 0) {  // every weight zero cannot happen for t in [0, 1]; keep one column
    out.column[0] = rows[0].row < 0 ? rows[0].row : rows[0].row * static_cast<int>(g.nx) + static_cast<int>(i0);
    out.weight[0] = 1.0;
    out.count = 1;
  }
  return out;
}

double GridSampler::columnHeight(int column, std::size_t k) const {
  if (column == GridColumns::kNorthPole) return northHeight_[k];
  if (column == GridColumns::kSouthPole) return southHeight_[k];
  if (column == GridColumns::kPadding) return kNaN;
  return grid_.heightAboveEllipsoidMeters[k * grid_.nx * grid_.ny + static_cast<std::size_t>(column)];
}

float GridSampler::columnValue(int column, std::size_t k) const {
  if (column == GridColumns::kNorthPole) return northValue_[k];
  if (column == GridColumns::kSouthPole) return southValue_[k];
  if (column == GridColumns::kPadding) return std::numeric_limits<float>::quiet_NaN();
  return grid_.values[k * grid_.nx * grid_.ny + static_cast<std::size_t>(column)];
}

glm::ivec3 GridSampler::closedSize() const {
  const bool wraps = grid_.wrapsLongitude && !grid_.curvilinear;  // reduced too: each row's copy of its column 0
  return glm::ivec3(static_cast<int>(grid_.nx) + (wraps ? 1 : 0), static_cast<int>(grid_.ny) + (poleCaps_ ? 2 : 0),
                    static_cast<int>(grid_.nz));
}

int GridSampler::closedHeightColumn(int tc, int tr) const {
  const int column = closedColumn(tc, tr);
  return column == GridColumns::kPadding ? closedColumn(closedRow(tr).columns - 1, tr) : column;
}

int GridSampler::closedColumn(int tc, int tr) const {
  const int nx = static_cast<int>(grid_.nx), ny = static_cast<int>(grid_.ny);
  const int r = tr - closedRowOffset();
  if (r < 0) return int{GridColumns::kSouthPole};
  if (r >= ny) return int{GridColumns::kNorthPole};
  if (grid_.reduced()) {
    const int n = static_cast<int>(grid_.rowLengthPoints[static_cast<std::size_t>(r)]);
    if (tc < n) return r * nx + tc;
    if (tc == n && grid_.wrapsLongitude) return r * nx;
    return int{GridColumns::kPadding};
  }
  return r * nx + (tc % nx);
}

GridSampler::ClosedRow GridSampler::closedRow(int tr) const {
  const int r = tr - closedRowOffset();
  if (r < 0 || r >= static_cast<int>(grid_.ny) || !grid_.reduced()) return {2, west_, 360.0};
  const auto row = static_cast<std::size_t>(r);
  return {static_cast<int>(grid_.rowLengthPoints[row]) + (grid_.wrapsLongitude ? 1 : 0), grid_.rowFirstLonDeg[row],
          grid_.rowSpacingDeg[row]};
}

glm::dvec2 GridSampler::closedLatLonDeg(int tc, int tr) const {
  const int nx = static_cast<int>(grid_.nx), ny = static_cast<int>(grid_.ny);
  const int r = tr - closedRowOffset();
  if (r < 0) return glm::dvec2(-90.0, grid_.lonDeg[0]);
  if (r >= ny) return glm::dvec2(90.0, grid_.lonDeg[0]);
  if (grid_.reduced()) {  // the copy of column 0 at column rowLength: one circle on
    const auto row = static_cast<std::size_t>(r);
    return glm::dvec2(grid_.latDeg[row], grid_.lonDegAt(row, static_cast<std::size_t>(tc)));
  }
  const auto row = static_cast<std::size_t>(r), column = static_cast<std::size_t>(tc % nx);
  const double lon = grid_.lonDegAt(row, column) + (tc >= nx ? 360.0 : 0.0);
  return glm::dvec2(grid_.latDegAt(row, column), lon);
}

std::optional<double> GridSampler::fractionalLevel(const GridColumns& cols, double heightMeters) const {
  const std::size_t nz = grid_.nz;
  if (nz == 0) return std::nullopt;
  auto heightAt = [&](std::size_t k) {
    double h = 0.0;
    for (int c = 0; c < cols.count; ++c) h += cols.weight[c] * columnHeight(cols.column[c], k);
    return h;
  };
  if (!(heightMeters >= heightAt(0) && heightMeters <= heightAt(nz - 1))) return std::nullopt;
  if (nz == 1) return 0.0;
  std::size_t lo = 0, hi = nz - 1;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    if (heightAt(mid) <= heightMeters) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const double hLo = heightAt(lo), hHi = heightAt(hi);
  const double f = hHi > hLo ? std::clamp((heightMeters - hLo) / (hHi - hLo), 0.0, 1.0) : 0.0;
  return static_cast<double>(lo) + f;
}

GridColumns heaviestColumn(GridColumns columns) {
  if (columns.count == 0) return columns;
  int best = 0;
  for (int c = 1; c < columns.count; ++c)
    if (columns.weight[c] > columns.weight[best]) best = c;
  columns.column[0] = columns.column[best];
  columns.weight[0] = 1.0;
  columns.count = 1;
  return columns;
}

VolumeSample GridSampler::sampleGeodetic(double latDeg, double lonDeg, double heightMeters,
                                         Interpolation interpolation) const {
  const GridVolume& g = grid_;
  if (g.nz == 0 || !(heightMeters >= minHeight_ && heightMeters <= maxHeight_)) return {};
  const std::optional<glm::dvec2> ij = horizontalIndex(latDeg, lonDeg);
  if (!ij) return {};
  GridColumns cols = columnsAt(*ij);
  if (interpolation == Interpolation::Nearest) cols = heaviestColumn(cols);
  const std::optional<double> level = fractionalLevel(cols, heightMeters);
  if (!level) return {};
  auto valueAt = [&](std::size_t k) {
    double v = 0.0;
    for (int c = 0; c < cols.count; ++c) {
      const float x = columnValue(cols.column[c], k);
      if (!std::isfinite(x)) return kNaN;
      v += cols.weight[c] * x;
    }
    return v;
  };
  const std::size_t lo = static_cast<std::size_t>(*level), hi = std::min(lo + 1, g.nz - 1);
  const double f = *level - static_cast<double>(lo);
  const double value = interpolation == Interpolation::Nearest ? valueAt(f < 0.5 ? lo : hi)
                                                               : (1.0 - f) * valueAt(lo) + f * valueAt(hi);
  if (!std::isfinite(value)) return {};
  return {VolumeSample::State::Echo, value};
}

std::optional<glm::dvec3> GridSampler::gridIndex(double latDeg, double lonDeg, double heightMeters) const {
  const std::optional<glm::dvec2> ij = horizontalIndex(latDeg, lonDeg);
  if (!ij) return std::nullopt;
  const std::optional<double> level = fractionalLevel(columnsAt(*ij), heightMeters);
  if (!level) return std::nullopt;
  return glm::dvec3(*ij, *level);
}

VolumeSample GridSampler::sample(const glm::dvec3& ecef, Interpolation interpolation) const {
  const globe::Geodetic p = globe::ecefToGeodetic(ecef);
  return sampleGeodetic(p.latDeg, p.lonDeg, p.heightMeters, interpolation);
}

namespace {

// A reduced grid's occupancy boxes (buildOccupancyGrid's comment): blocks of closed rows x
// reference columns x levels.
std::vector<OccupancyBox> reducedOccupancyBoxes(const GridSampler& s, const GridVolume& g, const glm::dvec3& centre,
                                                const glm::dmat3& toLocal) {
  std::vector<OccupancyBox> boxes;
  constexpr int kBx = 8, kBz = 4;
  const glm::ivec3 size = s.closedSize();
  const double west = s.reducedWestDeg(), step = s.reducedSpacingDeg();
  // Reference columns 0 .. columns - 1 span the grid's longitudes (a wrapping grid: the circle).
  const int columns = g.wrapsLongitude ? static_cast<int>(g.nx) + 1
                                       : static_cast<int>(std::ceil((g.reducedEastDeg() - west) / step - 1e-9)) + 1;
  for (int k0 = 0; k0 < std::max(size.z - 1, 1); k0 += kBz)
    for (int r0 = 0; r0 < size.y - 1; r0 += kBx)
      for (int u0 = 0; u0 < std::max(columns - 1, 1); u0 += kBx) {
        const int k1 = std::min(k0 + kBz, size.z - 1), r1 = std::min(r0 + kBx, size.y - 1),
                  u1 = std::min(u0 + kBx, std::max(columns - 1, 0));
        const double lon0 = west + u0 * step, lon1 = west + u1 * step;
        float maxValue = kOccupancyEmptyValue;
        double hLow = std::numeric_limits<double>::infinity(), hHigh = -hLow;
        for (int r = r0; r <= r1; ++r) {
          // The row's closed columns whose cells meet [lon0, lon1]: from a, the block's west edge
          // in the row's columns, over its width.
          const GridSampler::ClosedRow row = s.closedRow(r);
          const int last = row.columns - 1;
          const double a = (wrapFrom(lon0, row.firstLonDeg) - row.firstLonDeg) / row.spacingDeg;
          const double cells = (lon1 - lon0) / row.spacingDeg;
          auto take = [&](int tc) {
            const int column = s.closedColumn(tc, r);
            for (int k = k0; k <= k1; ++k) {
              const float v = s.columnValue(column, static_cast<std::size_t>(k));
              if (std::isfinite(v)) maxValue = std::max(maxValue, v);
            }
            const double low = static_cast<float>(s.columnHeight(column, static_cast<std::size_t>(k0)));
            const double high = static_cast<float>(s.columnHeight(column, static_cast<std::size_t>(k1)));
            if (std::isfinite(low)) hLow = std::min(hLow, low);
            if (std::isfinite(high)) hHigh = std::max(hHigh, high);
          };
          if (g.wrapsLongitude) {
            // The row repeats every `last` columns (its closed column `last` is column 0 again).
            for (int c = static_cast<int>(std::floor(a)); c <= static_cast<int>(std::ceil(a + cells)); ++c)
              take(last > 0 ? c % last : 0);
          } else {
            // A row of at most the circle: the block where the row holds it, west of its first
            // point taken one circle on or not.
            for (double start : {a, a - 360.0 / row.spacingDeg})
              for (int c = std::max(static_cast<int>(std::floor(start)), 0);
                   c <= std::min(static_cast<int>(std::ceil(start + cells)), last); ++c)
                take(c);
          }
        }
        if (maxValue == kOccupancyEmptyValue || !(hLow <= hHigh)) continue;
        glm::dvec3 lo(1e300), hi(-1e300);
        for (int r = r0; r <= r1; ++r) {
          const double lat = s.closedLatLonDeg(0, r).x;
          for (int u = u0; u <= u1; ++u)
            for (double hgt : {hLow, hHigh}) {
              const glm::dvec3 p = toLocal * (globe::geodeticToEcef({lat, west + u * step, hgt}) - centre);
              lo = glm::min(lo, p);
              hi = glm::max(hi, p);
            }
        }
        const double width = glm::length(glm::dvec2(hi - lo));
        const double margin = width * width / (8.0 * 6.35e6) + 0.05 * width + 10.0;
        boxes.push_back({lo - margin, hi + margin, maxValue});
      }
  return boxes;
}

}  // namespace

OccupancyGrid buildOccupancyGrid(const GridSampler& s) {
  const BoundingSphere sphere = s.boundingSphere();
  const bool global = sphere.centreEcef == glm::dvec3(0.0);
  const glm::dmat3 frame = global ? glm::dmat3(1.0) : [&] {
    const globe::Geodetic c = globe::ecefToGeodetic(sphere.centreEcef);
    return globe::enuAxes(c.latDeg, c.lonDeg);
  }();
  const glm::dmat3 toLocal = glm::transpose(frame);
  const glm::ivec3 size = s.closedSize();
  if (s.grid().reduced())
    return buildOccupancyGrid(sphere.centreEcef, frame, reducedOccupancyBoxes(s, s.grid(), sphere.centreEcef, toLocal),
                              glm::ivec3(128, 128, 32));
  std::vector<OccupancyBox> boxes;
  constexpr int kBx = 8, kBz = 4;
  for (int k0 = 0; k0 < size.z - 1; k0 += kBz)
    for (int r0 = 0; r0 < size.y - 1; r0 += kBx)
      for (int c0 = 0; c0 < size.x - 1; c0 += kBx) {
        const int k1 = std::min(k0 + kBz, size.z - 1), r1 = std::min(r0 + kBx, size.y - 1),
                  c1 = std::min(c0 + kBx, size.x - 1);
        float maxValue = kOccupancyEmptyValue;
        for (int k = k0; k <= k1; ++k)
          for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c) {
              const float v = s.columnValue(s.closedColumn(c, r), static_cast<std::size_t>(k));
              if (std::isfinite(v)) maxValue = std::max(maxValue, v);
            }
        if (maxValue == kOccupancyEmptyValue) continue;
        glm::dvec3 lo(1e300), hi(-1e300);
        for (int r = r0; r <= r1; ++r)
          for (int c = c0; c <= c1; ++c) {
            const glm::dvec2 ll = s.closedLatLonDeg(c, r);
            for (int k : {k0, k1}) {
              const double hgt = static_cast<float>(s.columnHeight(s.closedColumn(c, r), static_cast<std::size_t>(k)));
              const glm::dvec3 p = toLocal * (globe::geodeticToEcef({ll.x, ll.y, hgt}) - sphere.centreEcef);
              lo = glm::min(lo, p);
              hi = glm::max(hi, p);
            }
          }
        const double width = glm::length(glm::dvec2(hi - lo));
        const double margin = width * width / (8.0 * 6.35e6) + 0.05 * width + 10.0;
        boxes.push_back({lo - margin, hi + margin, maxValue});
      }
  return buildOccupancyGrid(sphere.centreEcef, frame, boxes, glm::ivec3(128, 128, 32));
}

}  // namespace atmoglobe::volume
