#include <atmoglobe/volume/RadarVolume.h>

namespace atmoglobe::volume {

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

}  // namespace atmoglobe::volume
