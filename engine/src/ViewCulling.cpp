#include <atmoglobe/engine/ViewCulling.h>

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Horizon.h>
#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/RadarVolumeSet.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace atmoglobe::engine {

bool sphereMayBeVisible(const Camera& camera, const volume::BoundingSphere& s) {
  const globe::ViewState view = camera.viewState();
  for (const glm::dvec4& p : view.frustumPlanesEcef)
    if (glm::dot(glm::dvec3(p), s.centreEcef) + p.w < -s.radiusMeters) return false;
  // Horizon: in scaled space (ECEF / (a, a, b)) the sphere lies within a ball of radius r / b
  // about c. For a point P of that ball outside the unit sphere, angle(P, c) <= asin(r'/|c|) and
  // acos(1/|P|) <= acos(1/(|c| + r')), so Q = m c/|c| with m = 1/cos(sum) hides all of them
  // when it is hidden (Horizon.h's rule); points inside the unit sphere are inside the Earth.
  const glm::dvec3 c = globe::ecefToScaledSpace(s.centreEcef);
  const double len = glm::length(c), r = s.radiusMeters / globe::kWgs84B;
  if (len <= r || len + r <= 1.0) return true;
  const double angle = std::asin(r / len) + std::acos(1.0 / (len + r));
  if (angle >= 0.5 * std::numbers::pi - 1e-9) return true;
  const glm::dvec3 q = c / len / std::cos(angle);
  return !globe::isScaledSpacePointOccluded(globe::ecefToScaledSpace(camera.eyeEcef()), q);
}

Result<RadarFootprint> radarFootprint(const std::string& path, double verticalExaggeration) {
  std::string file = path;
  if (volume::isRadarFileSet(path)) {
    auto files = volume::expandRadarPaths(path);
    if (!files) return files.forwardError();
    if (files->empty()) return makeError(path + ": no radar files");
    file = files->front();
  }
  volume::ReadOptions o;
  o.loadValues = false;
  auto v = volume::readRadarVolume(file, o);
  if (!v) return v.forwardError();
  double rangeMeters = 0.0;
  for (const volume::Sweep& s : v->sweeps) {
    if (s.gateCount == 0) continue;
    const double last = s.gateRangeMeters(s.gateCount - 1) + 0.5 * s.gateSpacingMeters;
    const double halfBeamRad = 0.5 * (v->beamWidthDeg > 0.0 ? v->beamWidthDeg : 2.0) * std::numbers::pi / 180.0;
    rangeMeters = std::max(rangeMeters, last + last * std::sin(halfBeamRad));
  }
  if (!(rangeMeters > 0.0)) rangeMeters = 500e3;
  RadarFootprint f;
  f.latDeg = v->site.latDeg;
  f.lonDeg = v->site.lonDeg;
  f.siteName = volume::siteTitle(v->site);
  volume::BoundingSphere& b = f.sphere;
  b.centreEcef = globe::geodeticToEcef({v->site.latDeg, v->site.lonDeg, v->site.antennaHeightMeters});
  // The geoid (|N| < 110 m) and the antenna's own height under exaggeration: a margin of 1 km.
  b.radiusMeters = rangeMeters * std::max(1.0, verticalExaggeration) + 1000.0 +
                   std::abs(v->site.antennaHeightMeters) * std::max(0.0, verticalExaggeration - 1.0);
  return f;
}

Result<volume::BoundingSphere> radarBoundingSphere(const std::string& path, double verticalExaggeration) {
  auto f = radarFootprint(path, verticalExaggeration);
  if (!f) return f.forwardError();
  return f->sphere;
}

std::vector<DeferredRadar> deferRadarsOutsideView(SceneDescription& scene, const Camera& camera) {
  std::vector<DeferredRadar> deferred;
  std::vector<VolumeLayerDescription> kept;
  std::vector<std::string> keptOrigins;
  for (std::size_t i = 0; i < scene.volumes.size(); ++i) {
    const VolumeLayerDescription& d = scene.volumes[i];
    const std::string origin = i < scene.origins.volumes.size() ? scene.origins.volumes[i] : std::string();
    if (d.kind == VolumeKind::Radar) {
      auto footprint = radarFootprint(d.path, scene.verticalExaggeration);
      if (footprint && !sphereMayBeVisible(camera, footprint->sphere)) {
        deferred.push_back(DeferredRadar{d, origin, std::move(*footprint)});
        continue;
      }
    }
    kept.push_back(d);
    if (i < scene.origins.volumes.size()) keptOrigins.push_back(origin);
  }
  scene.volumes = std::move(kept);
  scene.origins.volumes = std::move(keptOrigins);
  return deferred;
}

CullOutcome cullRadarsOutsideView(SceneDescription& scene, const Camera& camera) {
  CullOutcome out;
  for (DeferredRadar& d : deferRadarsOutsideView(scene, camera)) out.culled.push_back(std::move(d.description.path));
  for (const VolumeLayerDescription& d : scene.volumes) out.kept += d.kind == VolumeKind::Radar ? 1 : 0;
  return out;
}

std::size_t visibleGridStride(const volume::GridVolume& g) {
  return std::max<std::size_t>(1, std::max(g.nx, g.ny) / 256);
}

namespace {

// A grid point visibleGridWindow tests: its column (a reduced grid's on its reference axis), row,
// and the distance from the eye to the nearer of its bottom and top.
struct VisiblePoint {
  std::size_t column = 0, row = 0;
  double distanceMeters = 0.0;
};

// The points (every stride-th column and row) whose bottom or top projects into the frame (4 %
// margin) and is not hidden by the ellipsoid.
std::vector<VisiblePoint> visibleGridPoints(const Camera& camera, const volume::GridVolume& g) {
  std::vector<VisiblePoint> points;
  const std::size_t nx = g.nx, ny = g.ny, nz = g.nz;
  if (nx == 0 || ny == 0 || nz == 0) return points;
  const std::size_t stride = visibleGridStride(g);
  const double w = camera.widthPx(), h = camera.heightPx(), mx = 0.04 * w, my = 0.04 * h;
  const glm::dvec3 eye = camera.eyeEcef();
  // The distance to the point when it is visible, else a negative number.
  auto visible = [&](double lat, double lon, double height) {
    const glm::dvec3 p = globe::geodeticToEcef({lat, lon, height});
    const auto px = camera.projectToPixel(p);
    if (!px || px->x < -mx || px->x > w + mx || px->y < -my || px->y > h + my) return -1.0;
    // Behind the ellipsoid: the segment from the eye meets it (1 m short of the point itself).
    const glm::dvec3 d = p - eye;
    const auto hit = globe::intersectRayEllipsoid(eye, d);
    return !hit || glm::length(*hit - eye) >= glm::length(d) - 1.0 ? glm::length(d) : -1.0;
  };
  for (std::size_t j = 0; j < ny; j += stride) {
    for (std::size_t i = 0; i < g.rowLength(j); i += stride) {
      const double lat = g.latDegAt(j, i), lon = g.lonDegAt(j, i);
      const double bottom = visible(lat, lon, g.heightMeters(0, j, i));
      const double top = visible(lat, lon, g.heightMeters(nz - 1, j, i));
      if (bottom < 0.0 && top < 0.0) continue;
      std::size_t c = i;
      if (g.reduced()) {
        const double x = std::fmod(std::fmod(lon - g.reducedWestDeg(), 360.0) + 360.0, 360.0) / g.reducedSpacingDeg();
        c = std::min(nx - 1, static_cast<std::size_t>(std::llround(x)) % nx);
        c -= c % stride;
      }
      points.push_back({c, j, bottom < 0.0 ? top : top < 0.0 ? bottom : std::min(bottom, top)});
    }
  }
  return points;
}

}  // namespace

volume::GridWindow visibleGridWindow(const Camera& camera, const volume::GridVolume& g) {
  const std::size_t nx = g.nx, ny = g.ny;
  volume::GridWindow window;
  const std::vector<VisiblePoint> points = visibleGridPoints(camera, g);
  if (points.empty()) return window;
  const std::size_t stride = visibleGridStride(g);
  std::vector<char> column(nx, 0);
  std::size_t rowMin = ny, rowMax = 0;
  for (const VisiblePoint& p : points) {
    column[p.column] = 1;
    rowMin = std::min(rowMin, p.row), rowMax = std::max(rowMax, p.row);
  }
  // Rows: a stride of margin (the untested rows between).
  const std::size_t j0 = rowMin >= stride ? rowMin - stride : 0, j1 = std::min(ny - 1, rowMax + stride);
  window.firstRow = j0;
  window.rowCount = j1 - j0 + 1;
  std::vector<std::size_t> on;
  for (std::size_t i = 0; i < nx; i += stride)
    if (column[i]) on.push_back(i);
  window.firstColumn = 0;
  window.columnCount = nx;
  // A wrapping grid seen to a pole's row (a stride from it) takes every longitude.
  const bool poleRow = g.wrapsLongitude && (j0 == 0 || j1 >= ny - 1 - std::min(ny - 1, stride));
  if (g.wrapsLongitude && !poleRow) {
    // The shortest arc holding the visible columns: the complement of the largest gap.
    std::size_t gapStart = on.back(), gapLen = nx - on.back() + on.front();  // the gap across the seam
    for (std::size_t k = 1; k < on.size(); ++k)
      if (on[k] - on[k - 1] > gapLen) gapLen = on[k] - on[k - 1], gapStart = on[k - 1];
    const std::size_t first = (gapStart + gapLen) % nx, span = nx - gapLen;
    const std::size_t count = span + 2 * stride + 1;
    if (static_cast<double>(count - 1) * 360.0 / static_cast<double>(nx) <= 300.0) {
      window.firstColumn = (first + nx - stride % nx) % nx;
      window.columnCount = count;
    }
  } else if (!g.wrapsLongitude) {
    const std::size_t i0 = on.front() >= stride ? on.front() - stride : 0, i1 = std::min(nx - 1, on.back() + stride);
    window.firstColumn = i0;
    window.columnCount = i1 - i0 + 1;
  }
  return window;
}

volume::GridWindow nearGridWindow(const Camera& camera, const volume::GridVolume& g, std::size_t maxPoints,
                                  std::size_t maxColumns, std::size_t maxRows) {
  volume::GridWindow window;
  if (g.reduced() || g.curvilinear) return window;
  std::vector<VisiblePoint> points = visibleGridPoints(camera, g);
  if (points.empty()) return window;
  std::stable_sort(points.begin(), points.end(),
                   [](const VisiblePoint& a, const VisiblePoint& b) { return a.distanceMeters < b.distanceMeters; });
  const long nx = static_cast<long>(g.nx), ny = static_cast<long>(g.ny);
  const long stride = static_cast<long>(visibleGridStride(g));
  const long c0 = static_cast<long>(points.front().column);
  // Columns as signed offsets from the nearest point's (on a wrapping grid the shorter way round).
  auto offset = [&](std::size_t c) {
    long d = static_cast<long>(c) - c0;
    if (g.wrapsLongitude) d = ((d % nx) + nx + nx / 2) % nx - nx / 2;
    return d;
  };
  // The window of offsets [a, b] x rows [r, s] with a stride of margin, clipped to the grid.
  auto windowOf = [&](long a, long b, long r, long s) {
    volume::GridWindow w;
    const long first = std::max(0L, r - stride), last = std::min(ny - 1, s + stride);
    w.firstRow = static_cast<std::size_t>(first);
    w.rowCount = static_cast<std::size_t>(last - first + 1);
    if (g.wrapsLongitude) {
      // Never every column: such a window would wrap and close polar caps of its own over the
      // rows it leaves out (volume::GridSampler), where the rest of the grid is drawn.
      const long count = std::min(nx - 1, b - a + 1 + 2 * stride);
      w.columnCount = static_cast<std::size_t>(count);
      w.firstColumn = static_cast<std::size_t>(((c0 + a - stride) % nx + nx) % nx);
    } else {
      const long lo = std::max(0L, c0 + a - stride), hi = std::min(nx - 1, c0 + b + stride);
      w.firstColumn = static_cast<std::size_t>(lo);
      w.columnCount = static_cast<std::size_t>(hi - lo + 1);
    }
    return w;
  };
  long a = 0, b = 0, r = static_cast<long>(points.front().row), s = r;
  for (const VisiblePoint& p : points) {
    const long o = offset(p.column), row = static_cast<long>(p.row);
    const long na = std::min(a, o), nb = std::max(b, o), nr = std::min(r, row), ns = std::max(s, row);
    const volume::GridWindow w = windowOf(na, nb, nr, ns);
    if (w.columnCount * w.rowCount > maxPoints || w.columnCount > maxColumns || w.rowCount > maxRows) {
      if (window.empty()) return window;  // the nearest point's window alone does not fit
      break;
    }
    a = na, b = nb, r = nr, s = ns;
    window = w;
  }
  return window;
}

}  // namespace atmoglobe::engine
