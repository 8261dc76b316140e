#pragma once
// The rows of `atmoglobe gates`: one gate per line with its antenna coordinates, its WGS84
// position and its value, printed so that a user who recomputes the position from the row's own
// azimuth, elevation and range (geolocateGateExact, or any exact geodesic code) lands within
// 1 mm of the row's ECEF coordinates (GateCsvTest).
//
// Digits: the angles are the sweep's float values, printed with 9 decimals (rounding <= 5e-10
// deg: 4 um of arc at 460 km); ranges, heights and ECEF with 4 decimals (<= 0.05 mm); latitude
// and longitude with 10 decimals (<= 5e-11 deg: 6 um). Locale-independent (std::to_chars).
// Values: the shortest form that reads back to the same float; empty for no data, "-inf" for
// no echo.
#include <atmoglobe/volume/Geolocation.h>

#include <cstddef>
#include <string>

namespace atmoglobe::volume {

/// "sweep,ray,gate,azimuth_deg,elevation_deg,range_m,lat_deg,lon_deg,height_m,ecef_x,ecef_y,ecef_z,value\n"
const char* gateCsvHeader();

/// Appends one row (with its newline).
void appendGateCsvRow(std::string& line, std::size_t sweep, std::size_t ray, std::size_t gate, double azimuthDeg,
                      double elevationDeg, double rangeMeters, const GatePosition& position, const float* value);

}  // namespace atmoglobe::volume
