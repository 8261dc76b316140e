// Bad forecast-grid files: every case must give an error that names the file and the variable
// at fault and says what is wrong; never a crash, a hang or an allocation the file cannot back.
// Each file is a small CF grid written here that reads correctly when left intact (checked
// first), with one thing broken.
#include "NcTestFile.h"

#include <atmoglobe/volume/GridReader.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

using namespace atmoglobe::volume;
using atmoglobe_test::NcTestFile;

namespace {

struct Broken {
  bool latVariable = true;  ///< false: dimension lat has no coordinate variable
  double latValue0 = 10.0;  ///< first latitude (NaN, 95 ...)
  bool latMonotonic = true;
  std::string levUnits = "hPa";  ///< "1": no known vertical coordinate
  bool levVariable = true;
  double levValue0 = 1000.0;
  std::string formulaTerms;     ///< non-empty: hybrid with these terms
  std::size_t hybmLength = 3;   ///< != 3: inconsistent
  bool psOnOtherDims = false;   ///< ps on (time, lat2, lon): inconsistent
  double psValue00 = 100000.0;  ///< NaN: a missing surface pressure
  bool decreasingGeopotential = false;
  std::size_t hugeLevels = 0;  ///< > 0: lev dimension of this length (never written)
  bool twoD = false;           ///< ta2d (time, lat, lon) only
  int mode = NC_NETCDF4;
};

std::string dir() { return atmoglobe_test::freshTestDir("grid_bad_input"); }

/// lat 4 x lon 5 x lev 3 x time 2; ta (time, lev, lat, lon); optional hybrid terms and z.
void write(const std::string& path, const Broken& b) {
  NcTestFile f(path, b.mode);
  const std::size_t nz = b.hugeLevels ? b.hugeLevels : 3;
  f.dim("time", 2);
  f.dim("lev", nz);
  f.dim("lat", 4);
  f.dim("lat2", 3);
  f.dim("lon", 5);
  f.dim("nb", b.hybmLength);
  auto vt = f.var("time", NC_DOUBLE, {"time"});
  f.text(vt, "units", "hours since 2020-01-01");
  NcTestFile::Var vz;
  if (b.levVariable) {
    vz = f.var("lev", NC_DOUBLE, {"lev"});
    f.text(vz, "units", b.levUnits);
    if (!b.formulaTerms.empty()) {
      f.text(vz, "standard_name", "atmosphere_hybrid_sigma_pressure_coordinate");
      f.text(vz, "formula_terms", b.formulaTerms);
    }
  }
  NcTestFile::Var vy;
  if (b.latVariable) {
    vy = f.var("lat", NC_DOUBLE, {"lat"});
    f.text(vy, "units", "degrees_north");
  }
  auto vx = f.var("lon", NC_DOUBLE, {"lon"});
  f.text(vx, "units", "degrees_east");
  NcTestFile::Var va, vap, vb, vps, vgeo;
  if (b.twoD) {
    va = f.var("ta2d", NC_FLOAT, {"time", "lat", "lon"});
  } else {
    va = f.var("ta", NC_FLOAT, {"time", "lev", "lat", "lon"});
  }
  if (!b.formulaTerms.empty()) {
    vap = f.var("hyam", NC_DOUBLE, {"lev"});
    f.text(vap, "units", "Pa");
    vb = f.var("hybm", NC_DOUBLE, {b.hybmLength == 3 ? "lev" : "nb"});
    vps = f.var("aps", NC_DOUBLE, {"time", b.psOnOtherDims ? "lat2" : "lat", "lon"});
    f.text(vps, "units", "Pa");
  }
  if (b.decreasingGeopotential) {
    vgeo = f.var("z", NC_DOUBLE, {"time", "lev", "lat", "lon"});
    f.text(vgeo, "standard_name", "geopotential");
    f.text(vgeo, "units", "m2 s-2");
  }
  f.put(vt, {0, 1});
  if (b.levVariable && !b.hugeLevels) f.put(vz, {b.levValue0, 850, 500});
  if (b.latVariable) f.put(vy, {b.latValue0, b.latMonotonic ? 11.0 : 9.0, 12, 13});
  f.put(vx, {0, 1, 2, 3, 4});
  if (!b.hugeLevels) f.put(va, std::vector<double>(b.twoD ? 2 * 4 * 5 : 2 * 3 * 4 * 5, 1.0));
  if (!b.formulaTerms.empty()) {
    f.put(vap, {0, 20000, 30000});
    f.put(vb, std::vector<double>(b.hybmLength, 0.5));
    std::vector<double> ps(2 * (b.psOnOtherDims ? 3 : 4) * 5, 100000.0);
    ps[0] = b.psValue00;
    f.put(vps, ps);
  }
  if (b.decreasingGeopotential) {
    std::vector<double> z;
    for (int t = 0; t < 2; ++t)
      for (int k = 0; k < 3; ++k)
        for (int n = 0; n < 20; ++n) z.push_back(9.80665 * (k == 2 && n == 7 ? 10.0 : 1000.0 * (k + 1)));
    f.put(vgeo, z);
  }
}

/// The read fails with a message naming the file and each of `parts`.
void expectError(const std::string& path, std::initializer_list<std::string> parts, const std::string& variable = "") {
  GridReadOptions o;
  o.variable = variable;
  auto r = readGridVolume(path, o);
  ASSERT_FALSE(r.ok()) << "read succeeded: " << path;
  EXPECT_EQ(r.error().rfind(path, 0), 0u) << "the message starts with the file: " << r.error();
  for (const auto& p : parts)
    EXPECT_NE(r.error().find(p), std::string::npos) << "'" << p << "' missing in: " << r.error();
  // describe says the same (it reads the same layout and coordinates).
  auto d = describeGridFile(path, variable);
  EXPECT_FALSE(d.ok()) << "describe succeeded: " << path;
}

}  // namespace

TEST(GridBadInput, IntactFilesRead) {
  const std::string d = dir();
  write(d + "/plain.nc", {});
  Broken hybrid;
  hybrid.formulaTerms = "ap: hyam b: hybm ps: aps";
  hybrid.levUnits = "1";
  write(d + "/hybrid.nc", hybrid);
  for (const char* name : {"/plain.nc", "/hybrid.nc"}) {
    auto r = readGridVolume(d + name);
    EXPECT_TRUE(r.ok()) << name << ": " << r.error();
  }
}

TEST(GridBadInput, MissingCoordinateVariables) {
  const std::string d = dir();
  Broken b;
  b.latVariable = false;
  write(d + "/no_lat.nc", b);
  expectError(d + "/no_lat.nc", {"'/ta'", "no latitude/longitude"});
  Broken l;
  l.levVariable = false;
  write(d + "/no_lev.nc", l);
  expectError(d + "/no_lev.nc", {"'/ta'", "dimension 'lev'", "no coordinate variable", "unknown vertical coordinate"});
  Broken t;
  t.formulaTerms = "ap: hyam b: hybm ps: surface_pressure";
  t.levUnits = "1";
  write(d + "/no_ps.nc", t);
  expectError(d + "/no_ps.nc", {"'/lev'", "'surface_pressure'", "not in the file"});
}

TEST(GridBadInput, InconsistentSizes) {
  const std::string d = dir();
  Broken b;
  b.formulaTerms = "ap: hyam b: hybm ps: aps";
  b.levUnits = "1";
  b.hybmLength = 4;
  write(d + "/hybm.nc", b);
  expectError(d + "/hybm.nc", {"'/hybm'", "4 values", "one per level (3)", "inconsistent sizes"});
  Broken p;
  p.formulaTerms = "ap: hyam b: hybm ps: aps";
  p.levUnits = "1";
  p.psOnOtherDims = true;
  write(d + "/ps.nc", p);
  expectError(d + "/ps.nc", {"'/aps'", "inconsistent sizes"});
  // 2-D latitude/longitude on dimensions the variable does not have.
  {
    NcTestFile f(d + "/curv.nc");
    f.dim("lev", 2);
    f.dim("y", 3);
    f.dim("x", 4);
    f.dim("y2", 5);
    auto lev = f.var("lev", NC_DOUBLE, {"lev"});
    f.text(lev, "units", "hPa");
    auto la = f.var("lat", NC_DOUBLE, {"y2", "x"});
    f.text(la, "units", "degrees_north");
    auto lo = f.var("lon", NC_DOUBLE, {"y2", "x"});
    f.text(lo, "units", "degrees_east");
    auto q = f.var("q", NC_FLOAT, {"lev", "y", "x"});
    f.text(q, "coordinates", "lat lon");
    f.put(lev, {1000, 500});
  }
  expectError(d + "/curv.nc", {"'/lat'", "'/q'", "inconsistent sizes"}, "q");
}

TEST(GridBadInput, UnknownVerticalCoordinate) {
  const std::string d = dir();
  Broken b;
  b.levUnits = "1";
  write(d + "/lev_units.nc", b);
  expectError(d + "/lev_units.nc", {"'/ta'", "unknown vertical coordinate", "dimension 'lev'", "units '1'"});
  Broken p;
  p.levUnits = "1";
  p.formulaTerms = "a: hyam b: hybm";  // hybrid without ps
  write(d + "/terms.nc", p);
  expectError(d + "/terms.nc", {"'/lev'", "lacks the term 'ps'"});
  Broken two;
  two.twoD = true;
  write(d + "/two_d.nc", two);
  expectError(d + "/two_d.nc", {"'/ta2d'", "no vertical dimension"}, "ta2d");
}

TEST(GridBadInput, NanAndOutOfRangeCoordinates) {
  const std::string d = dir();
  Broken n;
  n.latValue0 = std::nan("");
  write(d + "/nan_lat.nc", n);
  expectError(d + "/nan_lat.nc", {"'/lat'", "index 0", "not a finite number"});
  Broken big;
  big.latValue0 = 95.0;
  big.latMonotonic = true;
  write(d + "/lat95.nc", big);
  // 95, 11, 12, 13 is not monotonic either: the range check comes first.
  expectError(d + "/lat95.nc", {"'/lat'", "95", "beyond +-90"});
  Broken m;
  m.latMonotonic = false;
  write(d + "/lat_order.nc", m);
  expectError(d + "/lat_order.nc", {"'/lat'", "not strictly monotonic"});
  Broken lev;
  lev.levValue0 = std::nan("");
  write(d + "/nan_lev.nc", lev);
  expectError(d + "/nan_lev.nc", {"'/lev'", "level 0", "not finite"});
  Broken ps;
  ps.formulaTerms = "ap: hyam b: hybm ps: aps";
  ps.levUnits = "1";
  ps.psValue00 = std::nan("");
  write(d + "/nan_ps.nc", ps);
  expectError(d + "/nan_ps.nc", {"'/aps'", "surface pressure missing"});
  Broken z;
  z.decreasingGeopotential = true;
  write(d + "/z.nc", z);
  expectError(d + "/z.nc", {"'/z'", "do not increase upwards", "row 1, column 2"});
}

TEST(GridBadInput, HeaderClaimingMoreThanTheFileHolds) {
  // A netCDF-4 file whose level dimension claims 2^28 levels that were never written: the
  // reader must refuse before allocating (checkReadable), naming the variable.
  const std::string d = dir();
  Broken b;
  b.hugeLevels = std::size_t{1} << 28;
  write(d + "/huge.nc", b);
  ASSERT_LT(std::filesystem::file_size(d + "/huge.nc"), 1u << 20);
  expectError(d + "/huge.nc", {"'/lev'", "claims"});
}

TEST(GridBadInput, TruncatedAndForeignFiles) {
  const std::string d = dir();
  for (int mode : {0, NC_NETCDF4}) {
    Broken b;
    b.mode = mode;
    const std::string whole = d + (mode ? "/whole4.nc" : "/whole3.nc");
    write(whole, b);
    ASSERT_TRUE(readGridVolume(whole).ok());
    const auto size = std::filesystem::file_size(whole);
    for (double fraction : {0.05, 0.3, 0.6, 0.9, 0.99}) {
      const std::string cut =
          d + "/cut" + std::to_string(mode) + "_" + std::to_string(static_cast<int>(fraction * 100)) + ".nc";
      std::filesystem::copy_file(whole, cut, std::filesystem::copy_options::overwrite_existing);
      std::filesystem::resize_file(cut, static_cast<std::uintmax_t>(static_cast<double>(size) * fraction));
      auto r = readGridVolume(cut);
      // Some cuts leave a readable header whose data netCDF-C then fails to read; some leave the
      // data intact (classic files keep the data at the end); none may crash, and every failure
      // names the file.
      if (!r.ok()) {
        EXPECT_EQ(r.error().rfind(cut, 0), 0u) << r.error();
      }
      if (fraction <= 0.3) {
        EXPECT_FALSE(r.ok()) << "a file cut to " << fraction << " still read";
      }
      EXPECT_FALSE(isGridFile(cut) && fraction <= 0.05);
    }
  }
  std::ofstream(d + "/text.nc") << "netcdf is not this\n";
  auto t = readGridVolume(d + "/text.nc");
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.error().rfind(d + "/text.nc", 0), 0u) << t.error();
  auto missing = readGridVolume(d + "/missing.nc");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("missing.nc"), std::string::npos);
}

TEST(GridBadInput, BadRequests) {
  const std::string d = dir();
  write(d + "/plain.nc", {});
  GridReadOptions o;
  o.variable = "nope";
  auto r = readGridVolume(d + "/plain.nc", o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("no variable 'nope' (grid variables: /ta)"), std::string::npos) << r.error();
  o = GridReadOptions{};
  o.crop.southDeg = 20;
  o.crop.northDeg = 10;
  r = readGridVolume(d + "/plain.nc", o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("crop"), std::string::npos) << r.error();
  o = GridReadOptions{};
  o.crop.westDeg = std::nan("");
  r = readGridVolume(d + "/plain.nc", o);
  ASSERT_FALSE(r.ok());
  o = GridReadOptions{};
  o.crop.firstLevel = 3;
  r = readGridVolume(d + "/plain.nc", o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("first level 3"), std::string::npos) << r.error();
  o = GridReadOptions{};
  o.timeIso8601 = "yesterday";
  r = readGridVolume(d + "/plain.nc", o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("'yesterday'"), std::string::npos) << r.error();
}

TEST(GridBadInput, ExtraDimensionsAndCamAttributes) {
  const std::string d = dir();
  // A file of ta (time, X, lev, lat, lon) with X chosen per case; lev in hPa, or CAM's hybrid
  // attributes naming hyam / hybm / PS.
  struct Case {
    std::string extraDim = "number";
    std::size_t extraLength = 2;
    std::string extraUnits;  ///< units of the extra dimension's coordinate ("" none)
    double extraValue0 = 0;  ///< NaN: a missing coordinate value
    bool cam = false;
    std::vector<std::string> camAttributes = {"A_var", "B_var", "PS_var"};
    std::size_t hyamLength = 3;
  };
  auto writeCase = [&](const std::string& path, const Case& c) {
    NcTestFile f(path);
    f.dim("time", 1);
    f.dim(c.extraDim, c.extraLength);
    f.dim("lev", 3);
    f.dim("nh", c.hyamLength);
    f.dim("lat", 2);
    f.dim("lon", 2);
    auto ve = f.var(c.extraDim, NC_DOUBLE, {c.extraDim});
    if (!c.extraUnits.empty()) f.text(ve, "units", c.extraUnits);
    auto vl = f.var("lev", NC_DOUBLE, {"lev"});
    f.text(vl, "units", c.cam ? "hybrid_sigma_pressure" : "hPa");
    if (c.cam) {
      for (const auto& a : c.camAttributes) f.text(vl, a, a == "A_var" ? "hyam" : a == "B_var" ? "hybm" : "PS");
    }
    auto vy = f.var("lat", NC_DOUBLE, {"lat"});
    f.text(vy, "units", "degrees_north");
    auto vx = f.var("lon", NC_DOUBLE, {"lon"});
    f.text(vx, "units", "degrees_east");
    auto va = f.var("hyam", NC_DOUBLE, {c.hyamLength == 3 ? "lev" : "nh"});
    auto vb = f.var("hybm", NC_DOUBLE, {"lev"});
    auto vps = f.var("PS", NC_DOUBLE, {"time", "lat", "lon"});
    f.text(vps, "units", "Pa");
    auto vt = f.var("ta", NC_FLOAT, {"time", c.extraDim, "lev", "lat", "lon"});
    std::vector<double> ev(c.extraLength);
    for (std::size_t i = 0; i < ev.size(); ++i) ev[i] = static_cast<double>(i);
    if (!ev.empty()) ev[0] = c.extraValue0;
    if (!ev.empty()) f.put(ve, ev);
    f.put(vl, c.cam ? std::vector<double>{200, 500, 900} : std::vector<double>{1000, 850, 500});
    f.put(vy, {0, 1});
    f.put(vx, {0, 1});
    f.put(va, std::vector<double>(c.hyamLength, 0.1));
    f.put(vb, {0.1, 0.5, 0.9});
    f.put(vps, std::vector<double>(4, 100000.0));
    if (c.extraLength) f.put(vt, std::vector<double>(c.extraLength * 12, 1.0));
  };
  {
    writeCase(d + "/intact.nc", {});
    Case cam;
    cam.cam = true;
    writeCase(d + "/intact_cam.nc", cam);
    for (const char* name : {"/intact.nc", "/intact_cam.nc"}) {
      auto r = readGridVolume(d + name);
      EXPECT_TRUE(r.ok()) << name << ": " << r.error();
    }
  }
  Case empty;
  empty.extraLength = 0;
  writeCase(d + "/empty_extra.nc", empty);
  expectError(d + "/empty_extra.nc", {"'/ta'", "empty dimension", "number 0"}, "ta");
  Case twoVertical;
  twoVertical.extraDim = "height";
  twoVertical.extraUnits = "m";
  writeCase(d + "/two_vertical.nc", twoVertical);
  expectError(d + "/two_vertical.nc", {"'/ta'", "'height'", "'lev'", "both vertical", "ambiguous"}, "ta");
  Case nanMember;
  nanMember.extraValue0 = std::nan("");
  writeCase(d + "/nan_member.nc", nanMember);
  {
    GridReadOptions o;
    o.member = 5;
    auto r = readGridVolume(d + "/nan_member.nc", o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find("no ensemble member 5"), std::string::npos) << r.error();
    EXPECT_EQ(r.error().rfind(d + "/nan_member.nc", 0), 0u) << r.error();
    o.member = 1;  // the second value is fine
    auto ok = readGridVolume(d + "/nan_member.nc", o);
    EXPECT_TRUE(ok.ok()) << ok.error();
  }
  Case noA;
  noA.cam = true;
  noA.camAttributes = {"B_var"};
  writeCase(d + "/cam_no_a.nc", noA);
  expectError(d + "/cam_no_a.nc", {"'/lev'", "A_var, PS_var"}, "ta");
  Case shortA;
  shortA.cam = true;
  shortA.hyamLength = 2;
  writeCase(d + "/cam_short_a.nc", shortA);
  expectError(d + "/cam_short_a.nc", {"'/hyam'", "2 values", "one per level (3)", "inconsistent sizes"}, "ta");
}
