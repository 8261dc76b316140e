#pragma once
// What the GRIB tests share: the sample files of ../shared/data/grids_grib, a per-test index cache,
// ecCodes' command-line tools as the independent reference (grib_get_data prints every point's
// latitude, longitude and value), and GRIB files made in the test through ecCodes' own encoder.
#include <eccodes.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace atmoglobe_test::grib {

inline std::string gribPath(const std::string& name) { return atmoglobe_test::testDataPath("grids_grib/" + name); }

/// A fresh cache directory for this test: the GRIB index is written there.
inline std::string useTestCache() {
  const std::string dir = atmoglobe_test::freshTestDir("grib_cache");
  setenv("ATMOGLOBE_CACHE_DIR", dir.c_str(), 1);
  return dir;
}

inline bool haveTool(const char* name) {
  return std::system((std::string("command -v ") + name + " >/dev/null").c_str()) == 0;
}

#define SKIP_WITHOUT_ECCODES_TOOLS()                                                                     \
  do {                                                                                                   \
    if (!atmoglobe_test::grib::haveTool("grib_get_data") || !atmoglobe_test::grib::haveTool("grib_set")) \
      GTEST_SKIP() << "grib_get_data/grib_set not found (apt-get install libeccodes-tools)";             \
  } while (false)

struct Point {
  double latDeg, lonDeg, value;  ///< value NaN where grib_get_data says missing
};

/// Every point of the messages of `file` matching `where` (grib_get_data -w), in the message's
/// order, positions to 1e-9 deg and values to 10 significant digits.
inline std::vector<Point> gribGetData(const std::string& file, const std::string& where) {
  const std::string cmd = "grib_get_data -m nan -F '%.10g' -L '%.9f %.9f' " +
                          (where.empty() ? std::string() : "-w " + where + " ") + "'" + file + "'";
  std::unique_ptr<FILE, decltype(&pclose)> p(popen(cmd.c_str(), "r"), &pclose);
  std::vector<Point> out;
  if (!p) return out;
  char line[256];
  while (std::fgets(line, sizeof line, p.get())) {
    Point pt{};
    char value[64];
    if (std::sscanf(line, "%lf %lf %63s", &pt.latDeg, &pt.lonDeg, value) != 3) continue;  // header lines
    pt.value = std::string(value) == "nan" ? std::nan("") : std::strtod(value, nullptr);
    out.push_back(pt);
  }
  return out;
}

/// Longitude difference wrapped to [-180, 180).
inline double lonDiff(double a, double b) { return std::remainder(a - b, 360.0); }

/// A key set on a message made by makeGribMessage, in order.
struct GribKey {
  std::string name;
  std::variant<std::string, long, double> value;
};

/// One GRIB message made by ecCodes from its sample `sample` ("GRIB1", "GRIB2",
/// "reduced_gg_pl_32_grib2" ...): the keys set in order, then the values (their count sets the
/// number of points). Empty with a test failure when ecCodes refuses a key.
inline std::string makeGribMessage(const char* sample, const std::vector<GribKey>& keys,
                                   const std::vector<double>& values) {
  std::unique_ptr<codes_handle, decltype(&codes_handle_delete)> h(codes_grib_handle_new_from_samples(nullptr, sample),
                                                                  &codes_handle_delete);
  if (!h) {
    ADD_FAILURE() << "no ecCodes sample " << sample;
    return {};
  }
  for (const GribKey& k : keys) {
    int err = CODES_SUCCESS;
    if (auto* s = std::get_if<std::string>(&k.value)) {
      std::size_t len = s->size();
      err = codes_set_string(h.get(), k.name.c_str(), s->c_str(), &len);
    } else if (auto* l = std::get_if<long>(&k.value)) {
      err = codes_set_long(h.get(), k.name.c_str(), *l);
    } else {
      err = codes_set_double(h.get(), k.name.c_str(), std::get<double>(k.value));
    }
    if (err != CODES_SUCCESS) {
      ADD_FAILURE() << "ecCodes: " << k.name << ": " << codes_get_error_message(err);
      return {};
    }
  }
  if (int err = codes_set_double_array(h.get(), "values", values.data(), values.size()); err != CODES_SUCCESS) {
    ADD_FAILURE() << "ecCodes: values: " << codes_get_error_message(err);
    return {};
  }
  const void* bytes = nullptr;
  std::size_t size = 0;
  if (codes_get_message(h.get(), &bytes, &size) != CODES_SUCCESS) return {};
  return std::string(static_cast<const char*>(bytes), size);
}

inline void writeFile(const std::string& path, const std::string& content) {
  std::ofstream(path, std::ios::binary) << content;
}

}  // namespace atmoglobe_test::grib
