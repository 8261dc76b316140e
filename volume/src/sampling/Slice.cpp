// Slices through volumes (Slice.h).
#include <atmoglobe/volume/Slice.h>

#include <atmoglobe/globe/ParallelFor.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/GridVolume.h>
#include <atmoglobe/volume/PolarVolume.h>

#include <algorithm>
#include <cmath>

namespace atmoglobe::volume {
namespace {

constexpr int kMaxSlicePixels = 16384;  // per side

Status validateRasterSize(int columns, int rows) {
  if (columns < 1 || rows < 1 || columns > kMaxSlicePixels || rows > kMaxSlicePixels) {
    return makeError("slice size " + std::to_string(columns) + " x " + std::to_string(rows) +
                     " px: each side must be in 1.." + std::to_string(kMaxSlicePixels));
  }
  return Ok{};
}

std::string numberText(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

const char* toString(SliceHeightDatum d) {
  return d == SliceHeightDatum::SeaLevel ? "above sea level" : "above the WGS84 ellipsoid";
}

Status validateBox(const LatLonBox& b, const std::string& what) {
  if (!std::isfinite(b.southDeg) || !std::isfinite(b.northDeg) || !std::isfinite(b.westDeg) ||
      !std::isfinite(b.eastDeg)) {
    return makeError(what + ": the box's bounds must be finite numbers");
  }
  if (!(b.southDeg >= -90.0 && b.northDeg <= 90.0 && b.southDeg < b.northDeg)) {
    return makeError(what + ": latitudes must satisfy -90 <= south < north <= 90 (got south " + numberText(b.southDeg) +
                     ", north " + numberText(b.northDeg) + ")");
  }
  if (!(b.westDeg < b.eastDeg && b.eastDeg - b.westDeg <= 360.0)) {
    return makeError(what + ": longitudes must satisfy west < east <= west + 360 (got west " + numberText(b.westDeg) +
                     ", east " + numberText(b.eastDeg) + ")");
  }
  return Ok{};
}

// --- GeodesicPath ---

Result<GeodesicPath> GeodesicPath::create(const std::vector<LatLon>& points) {
  if (points.size() < 2) {
    return makeError("a cross-section path needs at least two points, got " + std::to_string(points.size()));
  }
  GeodesicPath p;
  p.points_ = points;
  p.cumulativeMeters_.push_back(0.0);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::string what = "path point " + std::to_string(k + 1);
    if (auto st = globe::validateGeodetic({points[k].latDeg, points[k].lonDeg, 0.0}, what.c_str()); !st) {
      return st.forwardError();
    }
    if (k == 0) continue;
    const globe::GeodesicLine g =
        globe::geodesicInverse(points[k - 1].latDeg, points[k - 1].lonDeg, points[k].latDeg, points[k].lonDeg);
    if (!(g.distanceMeters >= 1.0)) {
      return makeError("path points " + std::to_string(k) + " and " + std::to_string(k + 1) +
                       " are less than 1 m apart: no direction between them");
    }
    // Half the shortest meridian circumference is ~20,004 km: geodesics between nearly antipodal
    // points are not unique, so the path would be ambiguous.
    if (g.distanceMeters > 1.99e7) {
      return makeError("path points " + std::to_string(k) + " and " + std::to_string(k + 1) +
                       " are nearly antipodal: the geodesic between them is not unique (add a point between)");
    }
    p.azimuthDeg_.push_back(g.azimuth1Deg);
    p.cumulativeMeters_.push_back(p.cumulativeMeters_.back() + g.distanceMeters);
  }
  return p;
}

globe::GeodesicPoint GeodesicPath::at(double distanceMeters) const {
  const double d = std::clamp(distanceMeters, 0.0, lengthMeters());
  // The segment holding d: the last k with cumulative[k] <= d (the last segment for d == length).
  const auto it = std::upper_bound(cumulativeMeters_.begin(), cumulativeMeters_.end(), d);
  std::size_t k = it == cumulativeMeters_.begin() ? 0 : static_cast<std::size_t>(it - cumulativeMeters_.begin()) - 1;
  k = std::min(k, azimuthDeg_.size() - 1);
  return globe::geodesicDirect(points_[k].latDeg, points_[k].lonDeg, azimuthDeg_[k], d - cumulativeMeters_[k]);
}

// --- SliceGeometry ---

Result<SliceGeometry> SliceGeometry::cappi(const CappiSpec& spec, const GeoidGrid* geoid) {
  if (auto st = validateRasterSize(spec.columns, spec.rows); !st) return st.forwardError();
  if (auto st = validateBox(spec.box, "CAPPI box"); !st) return st.forwardError();
  if (!std::isfinite(spec.heightMeters)) return makeError("CAPPI height must be a finite number");
  if (spec.datum == SliceHeightDatum::SeaLevel && !geoid) {
    return makeError("a height above sea level needs the EGM96 geoid grid");
  }
  SliceGeometry g(Kind::Cappi, spec.columns, spec.rows, spec.datum, geoid);
  g.x0_ = spec.box.westDeg;
  g.x1_ = spec.box.eastDeg;
  g.y0_ = spec.box.northDeg;
  g.y1_ = spec.box.southDeg;
  g.cappiHeight_ = spec.heightMeters;
  if (spec.pressurePa) {
    if (!(*spec.pressurePa > 0.0 && *spec.pressurePa < 2e5))
      return makeError("an isobaric section's pressure must be in (0, 2000) hPa, got " + numberText(*spec.pressurePa) +
                       " Pa");
    g.pressurePa_ = spec.pressurePa;
  }
  return g;
}

Result<SliceGeometry> SliceGeometry::crossSection(const CrossSectionSpec& spec, const GeoidGrid* geoid) {
  if (auto st = validateRasterSize(spec.columns, spec.rows); !st) return st.forwardError();
  auto path = GeodesicPath::create(spec.points);
  if (!path) return path.forwardError();
  if (!std::isfinite(spec.bottomMeters) || !std::isfinite(spec.topMeters) || !(spec.bottomMeters < spec.topMeters)) {
    return makeError("cross-section heights: need finite bottom < top (got " + numberText(spec.bottomMeters) + " .. " +
                     numberText(spec.topMeters) + " m)");
  }
  if (spec.datum == SliceHeightDatum::SeaLevel && !geoid) {
    return makeError("a height above sea level needs the EGM96 geoid grid");
  }
  SliceGeometry g(Kind::CrossSection, spec.columns, spec.rows, spec.datum, geoid);
  g.path_ = std::move(*path);
  g.x0_ = 0.0;
  g.x1_ = g.path_.lengthMeters();
  g.y0_ = spec.topMeters;
  g.y1_ = spec.bottomMeters;
  return g;
}

double SliceGeometry::ellipsoidalHeight(double latDeg, double lonDeg, double heightAboveDatum) const {
  if (datum_ == SliceHeightDatum::Ellipsoid) return heightAboveDatum;
  return heightAboveDatum + geoid_->undulationMeters(latDeg, lonDeg);
}

globe::Geodetic SliceGeometry::geodeticAt(double x, double y) const {
  if (kind_ == Kind::Cappi) {
    const double lat = yValue(y), lon = xValue(x);
    return {lat, lon, ellipsoidalHeight(lat, lon, cappiHeight_)};
  }
  const globe::GeodesicPoint p = path_.at(xValue(x));
  return {p.latDeg, p.lonDeg, ellipsoidalHeight(p.latDeg, p.lonDeg, yValue(y))};
}

glm::dvec3 SliceGeometry::ecefAt(double x, double y) const { return globe::geodeticToEcef(geodeticAt(x, y)); }

// --- sampling ---

VolumeSample sampleVolumes(const std::vector<const VolumeSampler*>& samplers, const glm::dvec3& ecef,
                           Interpolation interpolation) {
  VolumeSample out;  // NoData
  for (const VolumeSampler* s : samplers) {
    if (s->provablyEmpty(ecef)) continue;
    const VolumeSample v = s->sample(ecef, interpolation);
    if (v.state == VolumeSample::State::Echo) {
      if (out.state != VolumeSample::State::Echo || v.value > out.value) out = v;
    } else if (v.state == VolumeSample::State::NoEcho && out.state == VolumeSample::State::NoData) {
      out = v;
    }
  }
  return out;
}

SliceRaster sampleSlice(const std::vector<const VolumeSampler*>& samplers, const SliceGeometry& geometry,
                        Interpolation interpolation, int threads) {
  SliceRaster r;
  r.columns = geometry.columns();
  r.rows = geometry.rows();
  r.values.assign(static_cast<std::size_t>(r.columns) * static_cast<std::size_t>(r.rows),
                  std::numeric_limits<float>::quiet_NaN());
  auto row = [&](std::size_t jr) {
    const int j = static_cast<int>(jr);
    for (int i = 0; i < r.columns; ++i) {
      const VolumeSample s = sampleVolumes(samplers, geometry.ecefAt(i + 0.5, j + 0.5), interpolation);
      float& out = r.values[jr * static_cast<std::size_t>(r.columns) + static_cast<std::size_t>(i)];
      out = s.state == VolumeSample::State::Echo     ? static_cast<float>(s.value)
            : s.state == VolumeSample::State::NoEcho ? -std::numeric_limits<float>::infinity()
                                                     : std::numeric_limits<float>::quiet_NaN();
    }
  };
  globe::parallelFor(static_cast<std::size_t>(std::max(r.rows, 0)), row, static_cast<unsigned>(std::max(threads, 0)));
  summarizeSliceRaster(r);
  return r;
}

void summarizeSliceRaster(SliceRaster& r) {
  r.echoCount = r.noEchoCount = r.noDataCount = 0;
  r.minEcho = r.maxEcho = std::numeric_limits<float>::quiet_NaN();
  for (float v : r.values) {
    if (std::isnan(v)) {
      ++r.noDataCount;
    } else if (std::isinf(v)) {
      ++r.noEchoCount;
    } else {
      ++r.echoCount;
      r.minEcho = r.echoCount == 1 ? v : std::min(r.minEcho, v);
      r.maxEcho = r.echoCount == 1 ? v : std::max(r.maxEcho, v);
    }
  }
}

// --- extents ---

LatLonBox polarExtent(const PolarVolume& v) {
  const double radius = v.maxRangeMeters * 1.001;
  const double lat0 = v.site.latDeg, lon0 = v.site.lonDeg;
  LatLonBox b{lat0, lat0, lon0, lon0};
  for (int k = 0; k < 720; ++k) {
    const globe::GeodesicPoint p = globe::geodesicDirect(lat0, lon0, k * 0.5, radius);
    const double lon = lon0 + globe::wrapLongitudeDeg(p.lonDeg - lon0);
    b.southDeg = std::min(b.southDeg, p.latDeg);
    b.northDeg = std::max(b.northDeg, p.latDeg);
    b.westDeg = std::min(b.westDeg, lon);
    b.eastDeg = std::max(b.eastDeg, lon);
  }
  return b;
}

LatLonBox gridExtent(const GridVolume& g) {
  LatLonBox b;
  const auto [latMin, latMax] = std::minmax_element(g.latDeg.begin(), g.latDeg.end());
  const auto [lonMin, lonMax] = std::minmax_element(g.lonDeg.begin(), g.lonDeg.end());
  b.southDeg = *latMin;
  b.northDeg = *latMax;
  b.westDeg = *lonMin;
  b.eastDeg = g.wrapsLongitude ? b.westDeg + 360.0 : *lonMax;
  if (g.reduced() && !g.wrapsLongitude) b.eastDeg = g.reducedEastDeg();  // lonDeg: the reference axis
  return b;
}

}  // namespace atmoglobe::volume
