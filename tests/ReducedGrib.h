#pragma once
// GRIB files on reduced grids written in the test with ecCodes (its samples in
// /usr/share/eccodes/samples; no ../shared data): one message per level, values from an analytic
// function of the points' latitudes and longitudes as ecCodes computes them, exact to float
// (IEEE packing).
#include <eccodes.h>

#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::testutil {

struct ReducedGribSpec {
  /// An ecCodes sample: reduced_gg_pl_32_grib2 (N32 reduced Gaussian, 64 rows, 6114 points,
  /// north to south), reduced_ll_sfc_grib2 (0.36 degree reduced lat/lon, 501 rows, 313362
  /// points, rows of no point at its ends) ...
  std::string sample = "reduced_gg_pl_32_grib2";
  std::string typeOfLevel = "heightAboveSea";
  std::vector<long> levels = {500, 1500, 3000, 5000};  ///< `level` of each message (m for heights)
  bool southToNorth = false;                           ///< jScansPositively (first and last latitudes swapped)
  /// value(latitude, longitude, level) at each point.
  std::function<double(double, double, double)> field;
  /// Points to mark missing in a bitmap (none when unset).
  std::function<bool(double, double)> missing;
  /// Applied to each message before it is written (damage for the bad-input tests).
  std::function<void(codes_handle*)> tweak;
};

/// Every point's latitude and longitude of a message, as ecCodes gives them.
inline bool gribPoints(codes_handle* h, std::vector<double>& lat, std::vector<double>& lon) {
  std::size_t n = 0;
  if (codes_get_size(h, "values", &n) != CODES_SUCCESS) return false;
  lat.resize(n);
  lon.resize(n);
  return codes_get_double_array(h, "latitudes", lat.data(), &n) == CODES_SUCCESS &&
         codes_get_double_array(h, "longitudes", lon.data(), &n) == CODES_SUCCESS;
}

/// Writes `spec` to `path`; "" or what failed.
inline std::string writeReducedGrib(const std::string& path, const ReducedGribSpec& spec) {
  std::unique_ptr<FILE, decltype(&std::fclose)> out(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!out) return "cannot write " + path;
  for (long level : spec.levels) {
    std::unique_ptr<codes_handle, decltype(&codes_handle_delete)> h(
        codes_grib_handle_new_from_samples(nullptr, spec.sample.c_str()), &codes_handle_delete);
    if (!h) return "no ecCodes sample " + spec.sample;
    auto setString = [&](const char* key, const std::string& v) {
      std::size_t len = v.size();
      return codes_set_string(h.get(), key, v.c_str(), &len) == CODES_SUCCESS;
    };
    if (!setString("typeOfLevel", spec.typeOfLevel) || codes_set_long(h.get(), "level", level) != CODES_SUCCESS ||
        !setString("packingType", "grid_ieee"))
      return "cannot set the level or packing";
    if (spec.southToNorth) {
      double first = 0, last = 0;
      codes_get_double(h.get(), "latitudeOfFirstGridPointInDegrees", &first);
      codes_get_double(h.get(), "latitudeOfLastGridPointInDegrees", &last);
      codes_set_long(h.get(), "jScansPositively", 1);
      codes_set_double(h.get(), "latitudeOfFirstGridPointInDegrees", last);
      codes_set_double(h.get(), "latitudeOfLastGridPointInDegrees", first);
    }
    std::vector<double> lat, lon;
    if (!gribPoints(h.get(), lat, lon)) return "ecCodes gives no points for " + spec.sample;
    std::vector<double> values(lat.size());
    bool anyMissing = false;
    for (std::size_t p = 0; p < values.size(); ++p) {
      const bool gone = spec.missing && spec.missing(lat[p], lon[p]);
      values[p] = gone ? 9999.0 : static_cast<double>(static_cast<float>(spec.field(lat[p], lon[p], double(level))));
      anyMissing = anyMissing || gone;
    }
    if (anyMissing) {
      codes_set_double(h.get(), "missingValue", 9999.0);
      codes_set_long(h.get(), "bitmapPresent", 1);
    }
    if (codes_set_double_array(h.get(), "values", values.data(), values.size()) != CODES_SUCCESS)
      return "cannot set the values";
    if (spec.tweak) spec.tweak(h.get());
    const void* message = nullptr;
    std::size_t size = 0;
    if (codes_get_message(h.get(), &message, &size) != CODES_SUCCESS) return "cannot encode the message";
    if (std::fwrite(message, 1, size, out.get()) != size) return "cannot write " + path;
  }
  return {};
}

}  // namespace atmoglobe::testutil
