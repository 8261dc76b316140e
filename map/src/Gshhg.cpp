#include <atmoglobe/map/Gshhg.h>

#include <atmoglobe/io/NetcdfLock.h>

#include <netcdf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace atmoglobe::map {

char gshhgResolutionLetter(GshhgResolution r) { return "clihf"[static_cast<int>(r)]; }

std::string defaultGshhgDirectory() {
  if (const char* d = std::getenv("ATMOGLOBE_GSHHG_DIR"); d && *d) return d;
  return ATMOGLOBE_GSHHG_DIR;
}

std::string gshhgPath(const std::string& dir, GshhgKind kind, GshhgResolution resolution) {
  std::string p = dir;
  p.append(kind == GshhgKind::Shoreline ? "/binned_GSHHS_" : "/binned_border_");
  p.push_back(gshhgResolutionLetter(resolution));
  p.append(".nc");
  return p;
}

namespace {
std::string ncMessage(const std::string& path, const std::string& what, int status) {
  return path + ": " + what + ": " + nc_strerror(status);
}
}  // namespace

Result<std::unique_ptr<GshhgFile>> GshhgFile::open(const std::string& path, GshhgKind kind) {
  // netCDF-C is not thread-safe and the viewer's background loader reads grids meanwhile: every
  // call here holds the one library lock (io/NetcdfLock.h).
  const io::NetcdfLock lock;
  std::unique_ptr<GshhgFile> f(new GshhgFile());
  f->path_ = path;
  f->kind_ = kind;
  if (int st = nc_open(path.c_str(), NC_NOWRITE, &f->ncid_); st != NC_NOERR) {
    f->ncid_ = -1;
    return makeError(ncMessage(path, "cannot open as a GSHHG binned NetCDF file (apt-get install gmt-gshhg)", st));
  }
  auto var = [&](const char* name, int* id) -> Status {
    if (int st = nc_inq_varid(f->ncid_, name, id); st != NC_NOERR)
      return makeError(ncMessage(path, std::string("not a GSHHG binned file: no variable ") + name, st));
    return Ok{};
  };
  auto scalar = [&](const char* name, long long* out) -> Status {
    int id = -1;
    if (auto s = var(name, &id); !s) return s;
    int v = 0;
    if (int st = nc_get_var_int(f->ncid_, id, &v); st != NC_NOERR) return makeError(ncMessage(path, name, st));
    *out = v;
    return Ok{};
  };
  long long binMinutes = 0, binsAcross = 0, binsDown = 0, bins = 0;
  for (auto [name, out] : {std::pair<const char*, long long*>{"Bin_size_in_minutes", &binMinutes},
                           {"N_bins_in_360_longitude_range", &binsAcross},
                           {"N_bins_in_180_degree_latitude_range", &binsDown},
                           {"N_bins_in_file", &bins},
                           {"N_segments_in_file", &f->segmentCount_},
                           {"N_points_in_file", &f->pointCount_}}) {
    if (auto s = scalar(name, out); !s) return s.forwardError();
  }
  if (binMinutes <= 0 || binsAcross * binMinutes != 360 * 60 || binsDown * binMinutes != 180 * 60 ||
      bins != binsAcross * binsDown || f->segmentCount_ < 0 || f->pointCount_ < 0)
    return makeError(path + ": inconsistent GSHHG bin tables (bin size " + std::to_string(binMinutes) + " min, " +
                     std::to_string(binsAcross) + " x " + std::to_string(binsDown) + " bins, " + std::to_string(bins) +
                     " in the file)");
  f->binsAcross_ = static_cast<int>(binsAcross);
  f->binSizeDeg_ = static_cast<double>(binMinutes) / 60.0;
  int firstSeg = -1, nSeg = -1;
  for (auto [name, id] : {std::pair<const char*, int*>{"Id_of_first_segment_in_a_bin", &firstSeg},
                          {"N_segments_in_a_bin", &nSeg},
                          {"Id_of_first_point_in_a_segment", &f->varSegFirstPoint_},
                          {"Relative_longitude_from_SW_corner_of_bin", &f->varLon_},
                          {"Relative_latitude_from_SW_corner_of_bin", &f->varLat_}}) {
    if (auto s = var(name, id); !s) return s.forwardError();
  }
  if (kind == GshhgKind::Shoreline) {
    if (auto s = var("Embedded_npts_levels_exit_entry_for_a_segment", &f->varSegInfo_); !s) return s.forwardError();
  } else {
    if (auto s = var("N_points_for_a_segment", &f->varSegCount_); !s) return s.forwardError();
    if (auto s = var("Hierarchial_level_of_a_segment", &f->varSegLevel_); !s) return s.forwardError();
  }
  f->firstSegment_.resize(static_cast<std::size_t>(bins));
  f->segmentsInBin_.resize(static_cast<std::size_t>(bins));
  if (int st = nc_get_var_int(f->ncid_, firstSeg, f->firstSegment_.data()); st != NC_NOERR)
    return makeError(ncMessage(path, "Id_of_first_segment_in_a_bin", st));
  if (int st = nc_get_var_int(f->ncid_, nSeg, f->segmentsInBin_.data()); st != NC_NOERR)
    return makeError(ncMessage(path, "N_segments_in_a_bin", st));
  for (std::size_t b = 0; b < f->firstSegment_.size(); ++b) {
    const long long first = f->firstSegment_[b], n = f->segmentsInBin_[b];
    if (first < 0 || n < 0 || first + n > f->segmentCount_)
      return makeError(path + ": bin " + std::to_string(b) + " lists segments outside the file");
  }
  return f;
}

GshhgFile::~GshhgFile() {
  if (ncid_ < 0) return;
  const io::NetcdfLock lock;
  nc_close(ncid_);
}

GshhgBinBox GshhgFile::binBox(int bin) const {
  const double west = (bin % binsAcross_) * binSizeDeg_;
  const double north = 90.0 - (bin / binsAcross_) * binSizeDeg_;
  const double w = west >= 180.0 ? west - 360.0 : west;
  return {w, north - binSizeDeg_, w + binSizeDeg_, north};
}

std::vector<int> GshhgFile::binsOverlapping(double westDeg, double southDeg, double eastDeg, double northDeg) const {
  std::vector<int> bins;
  for (int b = 0; b < binCount(); ++b) {
    const GshhgBinBox box = binBox(b);
    if (box.northDeg < southDeg || box.southDeg > northDeg) continue;
    auto lonOverlap = [&](double w, double e) { return !(box.eastDeg < w || box.westDeg > e); };
    const bool overlap = westDeg <= eastDeg ? lonOverlap(westDeg, eastDeg)
                                            : lonOverlap(westDeg, 180.0) || lonOverlap(-180.0, eastDeg);
    if (overlap) bins.push_back(b);
  }
  return bins;
}

std::vector<int> GshhgFile::binsInside(const GshhgBinBox& box) const {
  std::vector<int> bins;
  if (binsAcross_ <= 0 || binSizeDeg_ <= 0.0) return bins;
  const int rows = binCount() / binsAcross_;
  constexpr double kEdge = 1e-9;  // box edges on the bin grid, up to rounding
  const int j0 = std::clamp(static_cast<int>(std::floor((90.0 - box.northDeg) / binSizeDeg_ + kEdge)), 0, rows);
  const int j1 = std::clamp(static_cast<int>(std::ceil((90.0 - box.southDeg) / binSizeDeg_ - kEdge)), j0, rows);
  const double west = box.westDeg < 0.0 ? box.westDeg + 360.0 : box.westDeg;  // columns start at 0 deg
  const int i0 = static_cast<int>(std::floor(west / binSizeDeg_ + kEdge)) % binsAcross_;
  const int across =
      std::clamp(static_cast<int>(std::lround((box.eastDeg - box.westDeg) / binSizeDeg_)), 0, binsAcross_);
  for (int j = j0; j < j1; ++j)
    for (int k = 0; k < across; ++k) bins.push_back(j * binsAcross_ + (i0 + k) % binsAcross_);
  return bins;
}

Result<std::vector<GeoPolyline>> GshhgFile::readBin(int bin, unsigned levelMask) const {
  std::vector<GeoPolyline> lines;
  if (bin < 0 || bin >= binCount()) return makeError(path_ + ": no bin " + std::to_string(bin));
  const auto b = static_cast<std::size_t>(bin);
  const std::size_t nSeg = static_cast<std::size_t>(segmentsInBin_[b]);
  if (nSeg == 0) return lines;
  const std::size_t start[1] = {static_cast<std::size_t>(firstSegment_[b])}, count[1] = {nSeg};
  std::vector<int> firstPoint(nSeg), npts(nSeg), level(nSeg);
  std::unique_lock lock(io::netcdfLibraryMutex());  // the reads only (io/NetcdfLock.h)
  if (int st = nc_get_vara_int(ncid_, varSegFirstPoint_, start, count, firstPoint.data()); st != NC_NOERR)
    return makeError(ncMessage(path_, "Id_of_first_point_in_a_segment", st));
  if (kind_ == GshhgKind::Shoreline) {
    std::vector<int> info(nSeg);
    if (int st = nc_get_vara_int(ncid_, varSegInfo_, start, count, info.data()); st != NC_NOERR)
      return makeError(ncMessage(path_, "Embedded_npts_levels_exit_entry_for_a_segment", st));
    for (std::size_t s = 0; s < nSeg; ++s) {
      npts[s] = static_cast<int>(static_cast<unsigned>(info[s]) >> 9);
      level[s] = (info[s] >> 6) & 7;
    }
  } else {
    if (int st = nc_get_vara_int(ncid_, varSegCount_, start, count, npts.data()); st != NC_NOERR)
      return makeError(ncMessage(path_, "N_points_for_a_segment", st));
    if (int st = nc_get_vara_int(ncid_, varSegLevel_, start, count, level.data()); st != NC_NOERR)
      return makeError(ncMessage(path_, "Hierarchial_level_of_a_segment", st));
  }
  // The bin's points are contiguous: read them at once.
  long long lo = firstPoint[0], hi = firstPoint[0];
  for (std::size_t s = 0; s < nSeg; ++s) {
    if (npts[s] < 0 || firstPoint[s] < 0 || firstPoint[s] + static_cast<long long>(npts[s]) > pointCount_)
      return makeError(path_ + ": bin " + std::to_string(bin) + " has a segment with points outside the file");
    lo = std::min<long long>(lo, firstPoint[s]);
    hi = std::max<long long>(hi, firstPoint[s] + static_cast<long long>(npts[s]));
  }
  const std::size_t pStart[1] = {static_cast<std::size_t>(lo)}, pCount[1] = {static_cast<std::size_t>(hi - lo)};
  std::vector<short> dx(pCount[0]), dy(pCount[0]);
  if (pCount[0] > 0) {
    if (int st = nc_get_vara_short(ncid_, varLon_, pStart, pCount, dx.data()); st != NC_NOERR)
      return makeError(ncMessage(path_, "Relative_longitude_from_SW_corner_of_bin", st));
    if (int st = nc_get_vara_short(ncid_, varLat_, pStart, pCount, dy.data()); st != NC_NOERR)
      return makeError(ncMessage(path_, "Relative_latitude_from_SW_corner_of_bin", st));
  }
  lock.unlock();
  const GshhgBinBox box = binBox(bin);
  const double scale = binSizeDeg_ / 65535.0;
  for (std::size_t s = 0; s < nSeg; ++s) {
    if (level[s] < 0 || level[s] > 31 || !(levelMask & (1u << level[s])) || npts[s] < 2) continue;
    GeoPolyline line;
    line.lonLatDeg.reserve(static_cast<std::size_t>(npts[s]));
    for (int k = 0; k < npts[s]; ++k) {
      const auto i = static_cast<std::size_t>(firstPoint[s] - lo + k);
      // Offsets are unsigned 16-bit values stored in NetCDF shorts.
      const double lon = box.westDeg + static_cast<std::uint16_t>(dx[i]) * scale;
      const double lat = box.southDeg + static_cast<std::uint16_t>(dy[i]) * scale;
      line.lonLatDeg.emplace_back(lon, std::clamp(lat, -90.0, 90.0));
    }
    lines.push_back(std::move(line));
  }
  return lines;
}

}  // namespace atmoglobe::map
