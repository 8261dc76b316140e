// radar_to_png: atmoglobe used as a library (examples/README.md). Reads a weather-radar volume,
// prints its site and where one of its gates lies, and renders it over the globe, headless (EGL,
// no window, no GPU needed), to a PNG.
//
//   radar_to_png RADAR_FILE [OUT.png]     (default OUT.png: radar.png)
//
// Exit status: 0 done, 1 bad input (the message names the file), 2 usage.
#include <atmoglobe/Version.h>
#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/Legend.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Image.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarLoad.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

using namespace atmoglobe;

static int fail(const std::string& message) {
  std::fprintf(stderr, "radar_to_png: %s\n", message.c_str());
  return 1;
}

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: radar_to_png RADAR_FILE [OUT.png]   (atmoglobe %s)\n", ATMOGLOBE_VERSION_STRING);
    return 2;
  }
  const std::string radarPath = argv[1];
  const std::string pngPath = argc == 3 ? argv[2] : "radar.png";

  // 1. Read the volume (any format atmoglobe reads, told by content) and bring the antenna to the
  //    WGS84 ellipsoid. Errors name the file.
  auto radar = volume::loadRadar(radarPath, volume::RadarLoadOptions{});
  if (!radar) return fail(radar.error());
  const volume::RadarVolume& vol = radar->volume;
  const volume::GeolocationSite& site = radar->site.site;
  std::printf("%s: %s, %zu sweeps, field %s\n", radarPath.c_str(), vol.format.c_str(), vol.sweeps.size(),
              vol.loadedField.name.c_str());
  std::printf("site %s: lat %.6f deg, lon %.6f deg, antenna %.1f m above the WGS84 ellipsoid\n", vol.site.name.c_str(),
              site.latDeg, site.lonDeg, site.antennaHeightEllipsoidMeters);

  // 2. Where gate 100 of ray 0 of the lowest sweep is: 4/3-Earth beam, WGS84 geodesic (exact path).
  if (vol.sweeps.empty() || vol.sweeps[0].rayCount() == 0) return fail(radarPath + ": no rays in the first sweep");
  const volume::Sweep& sweep = vol.sweeps[0];
  const std::uint32_t gate = std::min<std::uint32_t>(100, sweep.gateCount - 1);
  const volume::GatePosition p = volume::geolocateGateExact(site, volume::BeamModel{}, sweep.azimuthDeg[0],
                                                            sweep.elevationDeg[0], sweep.gateRangeMeters(gate));
  std::printf(
      "sweep 0 ray 0 gate %u (azimuth %.2f deg, elevation %.2f deg, range %.0f m): "
      "lat %.6f deg, lon %.6f deg, height %.1f m above the ellipsoid\n",
      gate, sweep.azimuthDeg[0], sweep.elevationDeg[0], sweep.gateRangeMeters(gate), p.latDeg, p.lonDeg,
      p.heightMeters);

  // 3. Render: a headless GL context, a globe without imagery (its base colour), coastlines and
  //    borders where Debian's gmt-gshhg is installed, the radar ray-marched in its own geometry.
  auto context = engine::HeadlessContextGL::create();
  if (!context) return fail(context.error());
  auto imagery = engine::openImagery({}, {});
  if (!imagery) return fail(imagery.error());
  auto renderer = engine::SceneRendererGL::create(*imagery);
  if (!renderer) return fail(renderer.error());
  if (auto map = (*renderer)->setMapContext(true); !map) std::fprintf(stderr, "no map: %s\n", map.error().c_str());
  engine::VolumeLayerDescription layer;
  layer.kind = engine::VolumeKind::Radar;
  layer.path = radarPath;  // defaults: reflectivity, colours by the field's kind, DVR, 250 m steps
  auto added = (*renderer)->addVolume(layer);
  if (!added) return fail(added.error());

  // The camera 1.6 deg south of the site, 150 km up, looking north 35 deg below the horizon.
  engine::CameraPose pose;
  pose.latDeg = site.latDeg - 1.6;
  pose.lonDeg = site.lonDeg;
  pose.heightMeters = 1.5e5;
  pose.headingDeg = 0.0;
  pose.pitchDeg = -35.0;
  const int width = 640, height = 360;
  const engine::Camera camera(pose, 50.0, width, height);
  auto target = engine::FramebufferGL::create(width, height);
  if (!target) return fail(target.error());
  auto image = (*renderer)->renderToImage(camera, {}, **target);
  if (!image) return fail(image.error());
  const engine::FrameLegend legend = (*renderer)->legendFor(camera);

  // A check that the radar drew something: the pixels that change when it is hidden.
  (*added)->visible = false;
  auto without = (*renderer)->renderToImage(camera, {}, **target);
  if (!without) return fail(without.error());
  std::size_t radarPixels = 0;
  const std::uint8_t* with = image->pixels.data();
  const std::uint8_t* bare = without->pixels.data();
  for (std::size_t i = 0; i < image->pixels.size(); i += 4)
    if (!std::equal(with + i, with + i + 4, bare + i)) ++radarPixels;

  // 4. Title, time, colour key and scale bar (SYNTHETIC DATA when the file says so), then the PNG.
  if (auto st = engine::drawFrameLegend(*image, legend); !st) return fail(st.error());
  if (auto st = globe::writePng(pngPath, *image); !st) return fail(st.error());
  std::printf("%s: %dx%d, %zu pixels drawn by the radar\n", pngPath.c_str(), width, height, radarPixels);
  return 0;
}
