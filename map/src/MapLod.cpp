#include <atmoglobe/map/MapLod.h>

namespace atmoglobe::map {

double maxSegmentMetersFor(GshhgResolution r) {
  constexpr double kMeters[] = {50000.0, 20000.0, 5000.0, 1000.0, 250.0};
  return kMeters[static_cast<int>(r)];
}

GshhgResolution gshhgResolutionForScale(double metresPerPixel) {
  if (metresPerPixel >= 12500.0) return GshhgResolution::Crude;
  if (metresPerPixel >= 2500.0) return GshhgResolution::Low;
  if (metresPerPixel >= 500.0) return GshhgResolution::Intermediate;
  if (metresPerPixel >= 100.0) return GshhgResolution::High;
  return GshhgResolution::Full;
}

Result<BoxMapLines> readBoxMapLines(const std::string& gshhgDir, double southDeg, double northDeg, double westDeg,
                                    double eastDeg, GshhgResolution resolution) {
  BoxMapLines out;
  out.resolution = resolution;
  struct Layer {
    GshhgKind kind;
    unsigned levels;
    std::vector<GeoPolyline>* lines;
  };
  for (const Layer& layer : {Layer{GshhgKind::Shoreline, kCoastLevels, &out.coasts},
                             Layer{GshhgKind::Border, kNationalBorderLevels, &out.borders},
                             Layer{GshhgKind::Border, kStateBorderLevels, &out.internal}}) {
    auto file = GshhgFile::open(gshhgPath(gshhgDir, layer.kind, resolution), layer.kind);
    if (!file) return file.forwardError();
    for (int bin : (*file)->binsOverlapping(westDeg, southDeg, eastDeg, northDeg)) {
      auto lines = (*file)->readBin(bin, layer.levels);
      if (!lines) return lines.forwardError();
      for (GeoPolyline& l : *lines) layer.lines->push_back(std::move(l));
    }
  }
  return out;
}

}  // namespace atmoglobe::map
