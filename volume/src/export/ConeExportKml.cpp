// KML encoder for the radar cones: one Model per sweep (the KMZ archive is ZipArchive.h's).
#include <atmoglobe/volume/ConeExport.h>

#include <cassert>
#include <cstdio>

namespace atmoglobe::volume {

namespace {

std::string xmlText(std::string_view in) {
  std::string out;
  for (char c : in) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else if (static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n') out += c;
  }
  return out;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace

std::string encodeConesKml(const ConeScene& scene, const std::vector<std::string>& daeHrefs) {
  assert(daeHrefs.size() == scene.cones.size());
  std::string s;
  s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<kml xmlns=\"http://www.opengis.net/kml/2.2\">\n<Document>\n";
  s += "  <name>" + xmlText(scene.title) + "</name>\n";
  s += "  <description>" +
       xmlText("Radar sweeps as textured cones (" +
               std::string(scene.straight ? "straight beams" : "beams bent by the 4/3 effective Earth radius model") +
               "). Antenna " + fixed(scene.antennaAltitudeMslMeters, 2) + " m above mean sea level; " +
               scene.site.datumNote) +
       "</description>\n";
  // All models share one location: the antenna. Their vertices are ENU metres from it.
  const std::string lon = fixed(scene.site.site.lonDeg, 9), lat = fixed(scene.site.site.latDeg, 9);
  const std::string alt = fixed(scene.antennaAltitudeMslMeters, 3);
  for (std::size_t i = 0; i < scene.cones.size(); ++i) {
    const Cone& c = scene.cones[i];
    const std::string stem = sweepStem(c.sweepIndex);
    s += "  <Placemark>\n    <name>" + stem + " " + fixed(c.mesh.elevationDeg, 2) + " deg</name>\n";
    s += "    <Model id=\"model-" + stem + "\">\n      <altitudeMode>absolute</altitudeMode>\n";
    s += "      <Location><longitude>" + lon + "</longitude><latitude>" + lat + "</latitude><altitude>" + alt +
         "</altitude></Location>\n";
    s += "      <Orientation><heading>0</heading><tilt>0</tilt><roll>0</roll></Orientation>\n";
    s += "      <Scale><x>1</x><y>1</y><z>1</z></Scale>\n";
    s += "      <Link><href>" + xmlText(daeHrefs[i]) + "</href></Link>\n    </Model>\n  </Placemark>\n";
  }
  s += "</Document>\n</kml>\n";
  return s;
}

}  // namespace atmoglobe::volume
