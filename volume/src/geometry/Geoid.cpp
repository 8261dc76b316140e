#include <atmoglobe/volume/Geoid.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

namespace atmoglobe::volume {

namespace {
std::uint64_t loadBe64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return v;
}
std::uint32_t loadBe32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
}  // namespace

Result<GeoidGrid> GeoidGrid::load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open geoid grid (Debian package proj-data provides it)");
  unsigned char header[40];
  if (!in.read(reinterpret_cast<char*>(header), sizeof header)) {
    return makeError(path + ": not a .gtx grid (shorter than its 40-byte header)");
  }
  GeoidGrid g;
  g.path_ = path;
  g.lat0Deg_ = std::bit_cast<double>(loadBe64(header));
  g.lon0Deg_ = std::bit_cast<double>(loadBe64(header + 8));
  g.dLatDeg_ = std::bit_cast<double>(loadBe64(header + 16));
  g.dLonDeg_ = std::bit_cast<double>(loadBe64(header + 24));
  g.rows_ = static_cast<std::int32_t>(loadBe32(header + 32));
  g.cols_ = static_cast<std::int32_t>(loadBe32(header + 36));
  const bool sane = std::isfinite(g.lat0Deg_) && std::isfinite(g.lon0Deg_) && g.dLatDeg_ > 1e-6 && g.dLonDeg_ > 1e-6 &&
                    g.dLatDeg_ <= 180 && g.dLonDeg_ <= 360 && g.rows_ >= 2 && g.cols_ >= 2 && g.rows_ <= 200000 &&
                    g.cols_ <= 400000;
  if (!sane) return makeError(path + ": .gtx header is not a plausible grid");
  const std::size_t count = static_cast<std::size_t>(g.rows_) * static_cast<std::size_t>(g.cols_);
  // Check the size against the file before allocating.
  in.seekg(0, std::ios::end);
  const auto fileSize = static_cast<std::uint64_t>(in.tellg());
  if (fileSize < 40 + count * 4) {
    return makeError(path + ": .gtx grid truncated (header says " + std::to_string(g.rows_) + " x " +
                     std::to_string(g.cols_) + " values)");
  }
  in.seekg(40);
  std::vector<unsigned char> raw(count * 4);
  if (!in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(raw.size()))) {
    return makeError(path + ": read error in .gtx grid");
  }
  g.values_.resize(count);
  for (std::size_t i = 0; i < count; ++i) g.values_[i] = std::bit_cast<float>(loadBe32(&raw[i * 4]));
  g.wrapsLongitude_ = std::abs(g.cols_ * g.dLonDeg_ - 360.0) < 1e-9 ||
                      std::abs((g.cols_ - 1) * g.dLonDeg_ - 360.0) < 1e-9;
  return g;
}

double GeoidGrid::undulationMeters(double latDeg, double lonDeg) const {
  assert(std::isfinite(latDeg) && std::isfinite(lonDeg));
  double fy = (latDeg - lat0Deg_) / dLatDeg_;
  fy = std::clamp(fy, 0.0, static_cast<double>(rows_ - 1));
  double fx = (lonDeg - lon0Deg_) / dLonDeg_;
  if (wrapsLongitude_) {
    const double period = 360.0 / dLonDeg_;
    fx = std::fmod(fx, period);
    if (fx < 0) fx += period;
  } else {
    fx = std::clamp(fx, 0.0, static_cast<double>(cols_ - 1));
  }
  const int y0 = std::min(static_cast<int>(fy), rows_ - 2);
  const int x0 = std::min(static_cast<int>(fx), cols_ - 1);
  // Column after x0: wraps to 0 for a global grid without a repeated column.
  const int x1 = x0 + 1 < cols_ ? x0 + 1 : (wrapsLongitude_ ? 0 : x0);
  const double ty = fy - y0, tx = fx - x0;
  auto at = [&](int y, int x) { return static_cast<double>(values_[static_cast<std::size_t>(y) * cols_ + x]); };
  const double south = at(y0, x0) * (1 - tx) + at(y0, x1) * tx;
  const double north = at(y0 + 1, x0) * (1 - tx) + at(y0 + 1, x1) * tx;
  return south * (1 - ty) + north * ty;
}

const Result<GeoidGrid>& defaultEgm96Grid() {
  static const Result<GeoidGrid> grid = [] {
    Result<GeoidGrid> g = GeoidGrid::load(kDefaultEgm96GridPath);
    if (!g) {
      return Result<GeoidGrid>(makeError(g.error() +
                                         "; the EGM96 geoid is needed to turn heights above mean sea level "
                                         "into heights above the WGS84 ellipsoid (or turn the conversion off, "
                                         "e.g. --no-geoid)"));
    }
    return g;
  }();
  return grid;
}

}  // namespace atmoglobe::volume
