// Rows of `atmoglobe gates` (GateCsv.h).
#include <atmoglobe/volume/GateCsv.h>

#include <atmoglobe/volume/RadarVolume.h>

#include <charconv>

namespace atmoglobe::volume {
namespace {

void appendFixed(std::string& line, double v, int decimals) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  line.append(buf, r.ptr);
}

void appendUnsigned(std::string& line, std::size_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  line.append(buf, r.ptr);
}

}  // namespace

const char* gateCsvHeader() {
  return "sweep,ray,gate,azimuth_deg,elevation_deg,range_m,lat_deg,lon_deg,height_m,ecef_x,ecef_y,ecef_z,value\n";
}

void appendGateCsvRow(std::string& line, std::size_t sweep, std::size_t ray, std::size_t gate, double azimuthDeg,
                      double elevationDeg, double rangeMeters, const GatePosition& p, const float* value) {
  appendUnsigned(line, sweep);
  line += ',';
  appendUnsigned(line, ray);
  line += ',';
  appendUnsigned(line, gate);
  line += ',';
  appendFixed(line, azimuthDeg, 9);
  line += ',';
  appendFixed(line, elevationDeg, 9);
  line += ',';
  appendFixed(line, rangeMeters, 4);
  line += ',';
  appendFixed(line, p.latDeg, 10);
  line += ',';
  appendFixed(line, p.lonDeg, 10);
  line += ',';
  appendFixed(line, p.heightMeters, 4);
  for (int c = 0; c < 3; ++c) {
    line += ',';
    appendFixed(line, p.ecef[c], 4);
  }
  line += ',';
  if (value && !isNoData(*value)) {
    if (isNoEcho(*value)) {
      line += "-inf";  // measured, nothing detected
    } else {
      char buf[32];
      const auto r = std::to_chars(buf, buf + sizeof buf, *value);  // shortest round-trip form
      line.append(buf, r.ptr);
    }
  }
  line += '\n';
}

}  // namespace atmoglobe::volume
