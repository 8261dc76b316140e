#include <atmoglobe/map/MapLod.h>

namespace atmoglobe::map {

GshhgResolution gshhgResolutionForHeight(double h) {
  if (h >= 6e6) return GshhgResolution::Crude;
  if (h >= 2e6) return GshhgResolution::Low;
  if (h >= 5e5) return GshhgResolution::Intermediate;
  if (h >= 8e4) return GshhgResolution::High;
  return GshhgResolution::Full;
}

double maxSegmentMetersFor(GshhgResolution r) {
  constexpr double kMeters[] = {50000.0, 20000.0, 5000.0, 1000.0, 250.0};
  return kMeters[static_cast<int>(r)];
}

}  // namespace atmoglobe::map
