#include <atmoglobe/engine/VolumeSourceGL.h>

#include <atmoglobe/engine/GridSourceGL.h>
#include <atmoglobe/engine/RadarNetworkSourceGL.h>
#include <atmoglobe/engine/RadarSourceGL.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/FieldKind.h>
#include <atmoglobe/volume/Geoid.h>

#include <cstdio>

namespace atmoglobe::engine {

std::string stepKeyPrefix(std::size_t layer) { return "layer:" + std::to_string(layer) + ":"; }

std::string stepKey(std::size_t layer, std::size_t step, bool gpu, double fraction) {
  std::string key = stepKeyPrefix(layer) + std::to_string(step);
  if (fraction > 0.0) {
    char f[32];
    std::snprintf(f, sizeof f, "+%.6f", fraction);
    key += f;
  }
  key += gpu ? ":gpu" : ":cpu";
  return key;
}

Result<std::unique_ptr<VolumeSourceGL>> openVolumeSource(const VolumeLayerDescription& d, SourceContext context) {
  switch (d.kind) {
    case VolumeKind::Radar: {
      // A set of several sites is a network, drawn as one volume under the overlap rule.
      auto network = RadarNetworkSourceGL::openIfNetwork(d, context);
      if (!network) return network.forwardError();
      if (*network) return std::unique_ptr<VolumeSourceGL>(std::move(*network));
      auto source = RadarSourceGL::open(d, context);
      if (!source) return source.forwardError();
      return std::unique_ptr<VolumeSourceGL>(std::move(*source));
    }
    case VolumeKind::Grid: {
      auto source = GridSourceGL::open(d, context);
      if (!source) return source.forwardError();
      return std::unique_ptr<VolumeSourceGL>(std::move(*source));
    }
  }
  return makeError(d.path + ": unknown layer kind");
}

Result<volume::TransferFunction> transferForLayer(const std::string& colors, const VolumeLayerSettings& settings,
                                                  const volume::FieldInfo& field, double nyquistMps,
                                                  const volume::ValueRange& range) {
  auto transfer = volume::transferForField(colors, field, nyquistMps, range);
  if (!transfer) return transfer.forwardError();
  volume::TransferFunction t = std::move(*transfer);
  if (settings.valueRange) t = volume::withValueRange(t, settings.valueRange->x, settings.valueRange->y);
  if (!settings.opacity.empty()) t = volume::withOpacityRamp(t, settings.opacity);
  if (settings.opacityPoints.size() >= 2) t = volume::withOpacityPoints(t, settings.opacityPoints);
  return t;
}

Result<VolumeRenderOptions> layerRenderOptions(const VolumeLayerDescription& d, const volume::FieldInfo& field,
                                               double nyquistMps, const volume::ValueRange& range) {
  VolumeRenderOptions o;
  o.render.mode = d.mode;
  o.render.interpolation = d.interpolation;
  o.render.stepMeters = d.stepMeters;
  o.render.samplesPerCell = samplesPerCellOf(d);
  o.render.isoValue = d.isoValue.value_or(defaultIsoValue(d.kind, range.minValue, range.maxValue));
  auto transfer = transferForLayer(d.colors, d.settings, field, nyquistMps, range);
  if (!transfer) return transfer.forwardError();
  o.render.transfer = std::move(*transfer);
  o.imageScale = d.imageScale;
  o.refineThreshold = d.refineThreshold;
  o.classification = d.classification;
  o.farField = d.farField.value_or(FarField::Off);
  return o;
}

bool isCropped(const VolumeLayerSettings& settings) {
  return !settings.crop.coversEveryLonLat() || !settings.crop.coversEveryHeight();
}

Result<const volume::GeoidGrid*> cropGeoid(const VolumeLayerSettings& settings, bool useGeoid) {
  if (settings.crop.coversEveryHeight() || !useGeoid) return static_cast<const volume::GeoidGrid*>(nullptr);
  const auto& g = volume::defaultEgm96Grid();
  if (!g) return makeError(g.error());
  return &*g;
}

std::string displayName(std::string name) {
  if (!name.empty() && name.front() == '/') name.erase(0, 1);
  return name;
}

}  // namespace atmoglobe::engine
