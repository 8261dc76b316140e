// The positions of GRIB's projected grids (rotated_ll, lambert, polar_stereographic, mercator,
// lambert_azimuthal_equal_area) from their projection parameters, through PROJ: the message's keys
// become a PROJ definition on the message's own Earth (a sphere of `radius`, or the spheroid of
// its axes), its first grid point is projected to plane coordinates, each point lies whole grid
// steps (Dx, Dy in metres; degrees for rotated grids) away in the scanning directions, and goes
// back to latitude and longitude by the inverse projection. ecCodes' own geo-iterator computes
// the same points; tests compare the two (tests/volume/GribProjectionTest.cpp).
//
// The latitudes and longitudes are those of the model's Earth (its sphere), used as WGS84
// geodetic ones, as every GRIB tool does: the model defines its grid on that Earth.
#include "GribInternal.h"
#include "GridInternal.h"

#include <eccodes.h>
#include <proj.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <memory>

namespace atmoglobe::volume::grib {

namespace {

std::string numText(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

/// A key as double; nullopt when the message lacks it.
std::optional<double> key(codes_handle* h, const char* name) {
  double v = 0;
  if (codes_get_double(h, name, &v) != CODES_SUCCESS || !std::isfinite(v)) return std::nullopt;
  return v;
}

long keyLong(codes_handle* h, const char* name, long fallback) {
  long v = fallback;
  if (codes_get_long(h, name, &v) != CODES_SUCCESS) return fallback;
  return v;
}

/// The message's Earth as PROJ parameters: "+R=..." or "+a=... +b=...".
Result<std::string> earthOf(codes_handle* h, const std::string& where) {
  if (keyLong(h, "earthIsOblate", 0) != 0) {
    auto a = key(h, "earthMajorAxisInMetres"), b = key(h, "earthMinorAxisInMetres");
    if (!a || !b || !(*a > 1e6 && *b > 1e6 && *b <= *a))
      return makeError(where +
                       ": an oblate Earth without usable axes (earthMajorAxisInMetres, earthMinorAxisInMetres)");
    return "+a=" + numText(*a) + " +b=" + numText(*b);
  }
  auto r = key(h, "radius");
  if (!r || !(*r > 1e6 && *r < 1e7)) return makeError(where + ": no usable Earth radius (key radius)");
  return "+R=" + numText(*r);
}

struct ProjDeleter {
  void operator()(PJ* p) const { proj_destroy(p); }
};
struct ContextDeleter {
  void operator()(PJ_CONTEXT* c) const { proj_context_destroy(c); }
};

Result<double> need(codes_handle* h, const char* name, const std::string& where) {
  auto v = key(h, name);
  if (!v) return makeError(where + ": key " + std::string(name) + " is missing or not a number");
  return *v;
}

/// The first of `names` the message has.
Result<double> needAny(codes_handle* h, std::initializer_list<const char*> names, const std::string& where) {
  std::string list;
  for (const char* n : names) {
    if (auto v = key(h, n)) return *v;
    list.append(list.empty() ? "" : ", ").append(n);
  }
  return makeError(where + ": none of the keys " + list + " is there");
}

}  // namespace

bool isProjectedGrid(const std::string& gridType) {
  return gridType == "rotated_ll" || gridType == "lambert" || gridType == "polar_stereographic" ||
         gridType == "mercator" || gridType == "lambert_azimuthal_equal_area";
}

Result<ProjectedGrid> projectedGrid(codes_handle* h, const std::string& gridType, long ni, long nj,
                                    const std::string& where) {
  if (!isProjectedGrid(gridType)) return makeError(where + ": grid type " + gridType + " is not a projected grid");
  if (ni < 1 || nj < 1) return makeError(where + ": a projected grid needs Ni x Nj points");
  auto lat1 = need(h, "latitudeOfFirstGridPointInDegrees", where);
  if (!lat1) return lat1.forwardError();
  auto lon1 = need(h, "longitudeOfFirstGridPointInDegrees", where);
  if (!lon1) return lon1.forwardError();
  if (std::fabs(*lat1) > 90.0) return makeError(where + ": first grid point latitude " + numText(*lat1) + " beyond 90");
  const bool iNegative = keyLong(h, "iScansNegatively", 0) != 0;
  const bool jPositive = keyLong(h, "jScansPositively", 0) != 0;
  ProjectedGrid g;
  double dx = 0, dy = 0;  // plane steps of a column and a row (metres; degrees for rotated grids)
  const bool rotated = gridType == "rotated_ll";
  if (rotated) {
    auto di = need(h, "iDirectionIncrementInDegrees", where), dj = need(h, "jDirectionIncrementInDegrees", where);
    auto spLat = need(h, "latitudeOfSouthernPoleInDegrees", where);
    auto spLon = need(h, "longitudeOfSouthernPoleInDegrees", where);
    if (!di) return di.forwardError();
    if (!dj) return dj.forwardError();
    if (!spLat) return spLat.forwardError();
    if (!spLon) return spLon.forwardError();
    // A rotation about the new polar axis is refused: decoders disagree on its sense (ecCodes 2.28
    // subtracts it from the final longitude, others add it to the rotated one), and models write 0.
    const double angle = key(h, "angleOfRotationInDegrees").value_or(0.0);
    if (angle != 0.0)
      return makeError(where + ": a rotated grid with an angle of rotation (" + numText(angle) +
                       " deg) is not read: its sense is not settled among GRIB decoders");
    dx = *di;
    dy = *dj;
    // The rotated pole: the grid's south pole at (spLat, spLon), so its north pole at (-spLat,
    // spLon + 180); PROJ's ob_tran takes the north pole's latitude and the central meridian.
    g.definition = "+proj=ob_tran +o_proj=longlat +o_lat_p=" + numText(-*spLat) +
                   " +o_lon_p=0 +lon_0=" + numText(*spLon) + " +R=1";
  } else {
    auto earth = earthOf(h, where);
    if (!earth) return earth.forwardError();
    // The plane steps: DxInMetres/DyInMetres (Lambert, polar stereographic), DiInMetres/DjInMetres
    // (Mercator), x/yDirectionGridLengthInMetres (Lambert azimuthal equal area).
    auto dxm = needAny(h, {"DxInMetres", "DiInMetres", "xDirectionGridLengthInMetres"}, where);
    auto dym = needAny(h, {"DyInMetres", "DjInMetres", "yDirectionGridLengthInMetres"}, where);
    if (!dxm) return dxm.forwardError();
    if (!dym) return dym.forwardError();
    dx = *dxm;
    dy = *dym;
    if (gridType == "lambert") {
      auto lov = need(h, "LoVInDegrees", where), lad = need(h, "LaDInDegrees", where);
      auto l1 = need(h, "Latin1InDegrees", where), l2 = need(h, "Latin2InDegrees", where);
      for (const auto* r : {&lov, &lad, &l1, &l2})
        if (!*r) return r->forwardError();
      g.definition = "+proj=lcc +lat_1=" + numText(*l1) + " +lat_2=" + numText(*l2) + " +lat_0=" + numText(*lad) +
                     " +lon_0=" + numText(*lov) + " " + *earth;
    } else if (gridType == "polar_stereographic") {
      auto lov = need(h, "orientationOfTheGridInDegrees", where);
      if (!lov) return lov.forwardError();
      const bool south = (keyLong(h, "projectionCentreFlag", 0) & 128) != 0;
      // GRIB 1 defines the plane true at 60 degrees in the hemisphere of the pole (ecCodes gives
      // LaDInDegrees = 60 for it either way); GRIB 2 gives LaD.
      const double lad = std::fabs(key(h, "LaDInDegrees").value_or(60.0)) * (south ? -1.0 : 1.0);
      g.definition = std::string("+proj=stere +lat_0=") + (south ? "-90" : "90") + " +lat_ts=" + numText(lad) +
                     " +lon_0=" + numText(*lov) + " " + *earth;
    } else if (gridType == "mercator") {
      auto lad = need(h, "LaDInDegrees", where);
      if (!lad) return lad.forwardError();
      g.definition = "+proj=merc +lat_ts=" + numText(*lad) + " +lon_0=" + numText(*lon1) + " " + *earth;
    } else {  // lambert_azimuthal_equal_area
      auto lat0 = need(h, "standardParallelInDegrees", where), lon0 = need(h, "centralLongitudeInDegrees", where);
      if (!lat0) return lat0.forwardError();
      if (!lon0) return lon0.forwardError();
      g.definition = "+proj=laea +lat_0=" + numText(*lat0) + " +lon_0=" + numText(*lon0) + " " + *earth;
    }
  }
  if (!(dx > 0 && dy > 0 && std::isfinite(dx) && std::isfinite(dy)))
    return makeError(where + ": grid steps " + numText(dx) + " x " + numText(dy) + " are not positive");

  // PROJ: one context per call (contexts are not shared between threads).
  std::unique_ptr<PJ_CONTEXT, ContextDeleter> ctx(proj_context_create());
  if (!ctx) return makeError(where + ": PROJ context could not be created");
  proj_log_level(ctx.get(), PJ_LOG_NONE);
  std::unique_ptr<PJ, ProjDeleter> p(proj_create(ctx.get(), g.definition.c_str()));
  if (!p)
    return makeError(where + ": PROJ refuses the projection '" + g.definition +
                     "': " + proj_context_errno_string(ctx.get(), proj_context_errno(ctx.get())));
  // Angular coordinates go in and out of proj_trans in radians (ob_tran's plane is angular too).
  const double planeScale = rotated ? M_PI / 180.0 : 1.0;
  PJ_COORD first = proj_coord(proj_torad(*lon1), proj_torad(*lat1), 0, 0);
  PJ_COORD xy0 = proj_trans(p.get(), PJ_FWD, first);
  if (!std::isfinite(xy0.xy.x) || !std::isfinite(xy0.xy.y))
    return makeError(where + ": the first grid point (" + numText(*lat1) + ", " + numText(*lon1) +
                     ") has no place on the projection '" + g.definition + "'");
  if (rotated) {  // the first point is given in the rotated frame already
    xy0.xy.x = proj_torad(*lon1);
    xy0.xy.y = proj_torad(*lat1);
  }
  const std::size_t nx = static_cast<std::size_t>(ni), ny = static_cast<std::size_t>(nj);
  g.latDeg.resize(nx * ny);
  g.lonDeg.resize(nx * ny);
  const double sx = (iNegative ? -dx : dx) * planeScale, sy = (jPositive ? dy : -dy) * planeScale;
  for (std::size_t r = 0; r < ny; ++r)
    for (std::size_t c = 0; c < nx; ++c) {
      PJ_COORD q = proj_coord(xy0.xy.x + static_cast<double>(c) * sx, xy0.xy.y + static_cast<double>(r) * sy, 0, 0);
      PJ_COORD ll = proj_trans(p.get(), PJ_INV, q);
      const double lat = proj_todeg(ll.lp.phi), lon = proj_todeg(ll.lp.lam);
      if (!std::isfinite(lat) || !std::isfinite(lon) || std::fabs(lat) > 90.0 + 1e-9)
        return makeError(where + ": grid point (row " + std::to_string(r) + ", column " + std::to_string(c) +
                         ") lies off the Earth of the projection '" + g.definition + "'");
      g.latDeg[r * nx + c] = std::clamp(lat, -90.0, 90.0);
      g.lonDeg[r * nx + c] = lon;
    }
  return g;
}

}  // namespace atmoglobe::volume::grib
