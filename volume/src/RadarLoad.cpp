#include <atmoglobe/volume/RadarLoad.h>

#include <atmoglobe/volume/RadarReader.h>

#include <utility>

namespace atmoglobe::volume {

Result<LoadedRadar> loadRadar(const std::string& path, const RadarLoadOptions& options) {
  ReadOptions read;
  read.fieldName = options.fieldName;
  Result<RadarVolume> radar = readRadarVolume(path, read);
  if (!radar) return radar.forwardError();  // the readers name the file
  Result<SiteResolution> site = resolveSite(radar->site, options.useGeoid);
  if (!site) return makeError(path + ": " + site.error());  // resolveSite names the site, not the file
  LoadedRadar out;
  out.volume = std::move(*radar);
  out.site = std::move(*site);
  if (options.buildRenderLayout) {
    Result<PolarVolume> layout = buildPolarVolume(out.volume, out.site, BeamModel{});
    if (!layout) return layout.forwardError();  // buildPolarVolume names the file (sourcePath)
    out.layout = std::move(*layout);
    if (!options.keepSweepValues) {
      for (Sweep& s : out.volume.sweeps) std::vector<float>().swap(s.values);
    }
  }
  return out;
}

}  // namespace atmoglobe::volume
