// KML (one Model per sweep) and KMZ (stored zip) encoders for the radar cones.
#include <atmoglobe/volume/ConeExport.h>

#include <array>
#include <cassert>
#include <cstdio>
#include <ctime>

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

void putLe(std::string& s, std::uint32_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

}  // namespace

std::string encodeConesKml(const ConeScene& scene, const std::vector<std::string>& daeHrefs) {
  assert(daeHrefs.size() == scene.cones.size());
  std::string s;
  s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<kml xmlns=\"http://www.opengis.net/kml/2.2\">\n<Document>\n";
  s += "  <name>" + xmlText(scene.title) + "</name>\n";
  s += "  <description>" +
       xmlText("Radar sweeps as textured cones (" + std::string(scene.straight ? "straight beams" : "beams bent by the 4/3 effective Earth radius model") +
               "). Antenna " + fixed(scene.antennaAltitudeMslMeters, 2) + " m above mean sea level; " + scene.site.datumNote) +
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

std::uint32_t crc32(std::string_view bytes) {
  static const std::array<std::uint32_t, 256> kTable = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFu;
  for (char ch : bytes) c = kTable[(c ^ static_cast<std::uint8_t>(ch)) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

std::string encodeStoredZip(const std::vector<std::pair<std::string, std::string>>& entries) {
  // PKWARE APPNOTE: local file header + data per entry, central directory, end record. Stored
  // (method 0): no compression, so the sizes are the data sizes. DOS time of "now".
  assert(entries.size() < 0xFFFF);
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  const std::uint32_t dosTime = static_cast<std::uint32_t>((tm.tm_hour << 11) | (tm.tm_min << 5) | (tm.tm_sec / 2));
  const std::uint32_t dosDate =
      static_cast<std::uint32_t>((std::max(tm.tm_year - 80, 0) << 9) | ((tm.tm_mon + 1) << 5) | tm.tm_mday);
  std::string out, central;
  for (const auto& [name, data] : entries) {
    assert(data.size() < 0xFFFFFFFFull && name.size() < 0xFFFF);
    const std::uint32_t crc = crc32(data);
    const std::uint32_t offset = static_cast<std::uint32_t>(out.size());
    const std::uint32_t size = static_cast<std::uint32_t>(data.size());
    putLe(out, 0x04034b50, 4);
    putLe(out, 20, 2);  // version needed: 2.0
    putLe(out, 0, 2);   // flags
    putLe(out, 0, 2);   // method: stored
    putLe(out, dosTime, 2);
    putLe(out, dosDate, 2);
    putLe(out, crc, 4);
    putLe(out, size, 4);
    putLe(out, size, 4);
    putLe(out, static_cast<std::uint32_t>(name.size()), 2);
    putLe(out, 0, 2);  // extra length
    out += name;
    out += data;

    putLe(central, 0x02014b50, 4);
    putLe(central, (3u << 8) | 20u, 2);  // made by: Unix, 2.0
    putLe(central, 20, 2);
    putLe(central, 0, 2);
    putLe(central, 0, 2);
    putLe(central, dosTime, 2);
    putLe(central, dosDate, 2);
    putLe(central, crc, 4);
    putLe(central, size, 4);
    putLe(central, size, 4);
    putLe(central, static_cast<std::uint32_t>(name.size()), 2);
    putLe(central, 0, 2);  // extra
    putLe(central, 0, 2);  // comment
    putLe(central, 0, 2);  // disk
    putLe(central, 0, 2);  // internal attributes
    putLe(central, 0100644u << 16, 4);  // external: regular file rw-r--r--
    putLe(central, offset, 4);
    central += name;
  }
  assert(out.size() + central.size() < 0xFFFFFFFFull);
  const std::uint32_t centralOffset = static_cast<std::uint32_t>(out.size());
  out += central;
  putLe(out, 0x06054b50, 4);
  putLe(out, 0, 2);
  putLe(out, 0, 2);
  putLe(out, static_cast<std::uint32_t>(entries.size()), 2);
  putLe(out, static_cast<std::uint32_t>(entries.size()), 2);
  putLe(out, static_cast<std::uint32_t>(central.size()), 4);
  putLe(out, centralOffset, 4);
  putLe(out, 0, 2);
  return out;
}

}  // namespace atmoglobe::volume
