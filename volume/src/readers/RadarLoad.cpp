#include <atmoglobe/volume/RadarLoad.h>

#include <atmoglobe/volume/RadarReader.h>
#include <atmoglobe/volume/RadarVolumeSet.h>

#include <utility>

namespace atmoglobe::volume {

Result<LoadedRadar> loadRadar(const std::string& path, const RadarLoadOptions& options) {
  ReadOptions read;
  read.fieldName = options.fieldName;
  read.nexradSiteList = options.nexradSiteList;
  Result<RadarVolume> radar = makeError(path + ": not read");
  if (isRadarFileSet(path)) {
    auto paths = expandRadarPaths(path);
    if (!paths) return paths.forwardError();
    RadarSetOptions set;
    set.read = read;
    set.label = path;
    radar = readRadarVolumeSet(*paths, set);
  } else {
    radar = readRadarVolume(path, read);
  }
  if (!radar) return radar.forwardError();  // the readers name the file
  Result<SiteResolution> site = resolveSite(radar->site, options.useGeoid);
  if (!site) return makeError(path + ": " + site.error());  // resolveSite names the site, not the file
  LoadedRadar out;
  out.volume = std::move(*radar);
  out.site = std::move(*site);
  // What users see of the load (render/view/gates/export-cones print the note): where the
  // position came from when not the file, and what the readers repaired or found missing.
  if (!out.volume.siteLocationSource.empty())
    out.site.datumNote += "; position from the " + out.volume.siteLocationSource;
  for (const std::string& w : out.volume.warnings) out.site.datumNote += "\nwarning: " + w;
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
