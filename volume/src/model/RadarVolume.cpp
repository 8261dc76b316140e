#include <atmoglobe/volume/RadarVolume.h>

#include <algorithm>
#include <cstdio>

namespace atmoglobe::volume {

std::string siteTitle(const RadarSite& site) {
  if (site.placeName.empty() || site.placeName == site.name) return site.name;
  if (site.name.empty()) return site.placeName;
  return site.name + " (" + site.placeName + ")";
}

const char* toString(HeightDatum d) {
  switch (d) {
    case HeightDatum::MeanSeaLevel: return "msl";
    case HeightDatum::Ellipsoid: return "wgs84_ellipsoid";
  }
  return "unknown";
}

const char* toString(SweepMode m) {
  switch (m) {
    case SweepMode::Ppi: return "PPI";
    case SweepMode::Rhi: return "RHI";
    case SweepMode::Other: return "other";
  }
  return "unknown";
}

namespace {
std::string formatAngle(double deg) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", deg);
  return buf;
}
}  // namespace

void sortSweepsByAngle(RadarVolume& v) {
  std::vector<std::size_t> order(v.sweeps.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return v.sweeps[a].fixedAngleDeg < v.sweeps[b].fixedAngleDeg; });
  bool changed = false;
  for (std::size_t i = 0; i < order.size(); ++i) changed = changed || order[i] != i;
  if (!changed) return;
  std::string stored;
  for (const Sweep& s : v.sweeps) stored += (stored.empty() ? "" : ", ") + formatAngle(s.fixedAngleDeg);
  std::vector<Sweep> sorted;
  sorted.reserve(v.sweeps.size());
  for (std::size_t i : order) sorted.push_back(std::move(v.sweeps[i]));
  v.sweeps = std::move(sorted);
  v.warnings.push_back("sweeps stored out of elevation order (" + stored + " deg) are sorted by elevation");
}

}  // namespace atmoglobe::volume
