#pragma once
// The PPI image of one sweep as an RGBA texture in (azimuth, range) layout.
//
// One row per ray, rows sorted by azimuth (clockwise from north), one column per gate (column j
// holds gate j, whose centre is at firstGateRangeMeters + j * gateSpacingMeters). Each row covers
// an azimuth interval: from the midpoint with the previous ray to the midpoint with the next, so
// irregular ray spacing maps by azimuth, not by index. Where two neighbouring rays are further
// apart than 2.5 times the median spacing (missing rays, sector scans), each keeps half a median
// spacing and a fully transparent row fills the gap. Duplicate azimuths keep the first ray.
// Pixels are transparent (0,0,0,0) where the value is no echo, no data or below the colour table.
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <cstdint>
#include <vector>

namespace atmoglobe::volume {

struct SweepImage {
  int width = 0;                           ///< columns = gates used
  int height = 0;                          ///< rows = rays (+ gap rows)
  std::vector<std::uint8_t> rgba;          ///< row-major RGBA8, row 0 first (= top of a PNG, v = 0 in glTF)
  std::vector<double> rowStartAzimuthDeg;  ///< row i covers [start, end) degrees; increasing; the
  std::vector<double> rowEndAzimuthDeg;    ///< rows tile one full turn from rowStartAzimuthDeg[0]
  std::vector<int> rowRay;                 ///< source ray of each row; -1 for a transparent gap row
  double firstGateRangeMeters = 0.0;       ///< centre of column 0 (m)
  double gateSpacingMeters = 0.0;          ///< column width (m)
};

/// Builds the image of `sweep` over its first `gateCount` gates with colours from `table`.
/// Preconditions (asserted; the exporter checks them on external data first): at least one ray,
/// 0 < gateCount <= sweep.gateCount, values loaded (size rays * sweep.gateCount), finite azimuths.
SweepImage makeSweepImage(const Sweep& sweep, const ColorTable& table, std::uint32_t gateCount);

/// Texture coordinate v in [0, 1] (0 = top of row 0) of an azimuth (degrees, any value: wrapped
/// into the image's turn). Exact: linear inside the row that holds the azimuth.
double sweepImageV(const SweepImage& image, double azimuthDeg);

/// Texture coordinate u in [0, 1] of a slant range (m): column j spans
/// [first + (j - 0.5) spacing, first + (j + 0.5) spacing).
double sweepImageU(const SweepImage& image, double rangeMeters);

/// PNG bytes of the image (globe::encodePng). Empty on an encoder failure.
std::vector<std::uint8_t> encodeSweepImagePng(const SweepImage& image);

}  // namespace atmoglobe::volume
