// Bad input for the CfRadial and ODIM_H5 readers (and truncated Sigmet/Rainbow files; their own
// tests truncate them at many more offsets): every case must give an error naming
// the file and the problem, never crash, hang or allocate what the file cannot hold.
// (Run once under -DATMOGLOBE_SANITIZE=ON to check the "no crash" part with ASan/UBSan.)
//
// The bad files are written here, into the test output directory: small CfRadial and
// ODIM files made with netCDF-C (each first checked to read correctly when left intact, so
// the failures below come from the one thing that was broken), truncated copies of the
// real files, random bytes, an empty file and a text file.
#include <atmoglobe/volume/CfRadialReader.h>
#include <atmoglobe/volume/OdimReader.h>
#include <atmoglobe/volume/RadarReader.h>

#include <gtest/gtest.h>
#include <netcdf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

using namespace atmoglobe::volume;

namespace {

const std::string kData = atmoglobe_test::testDataDir();

std::string outDir() {
  const auto d = std::filesystem::path(ATMOGLOBE_TEST_OUTPUT_DIR) / "bad_input";
  std::filesystem::create_directories(d);
  return d.string();
}

void check(int status) { ASSERT_EQ(status, NC_NOERR) << nc_strerror(status); }

// ---------------------------------------------------------------- synthetic CfRadial
struct CfSpec {
  bool netcdf4 = false;
  bool withStartIndex = true;
  bool withRange = true;
  bool nanAzimuth = false;     ///< ray 1 (inside sweep 0) gets azimuth NaN
  bool unlimitedTime = false;  ///< time as the record dimension (for the numrecs patch)
};

/// 2 sweeps out of 5 rays x 3 gates: sweep 0 = rays 0-1 at 1.5 deg, ray 2 is a transition
/// ray, sweep 1 = rays 3-4 at 0.5 deg (so sorting puts it first). Field DBZ: short with
/// scale 0.5, offset -10, _FillValue -999; raw value = 10 * ray + gate, gate (4,2) is fill.
void writeCfRadial(const std::string& path, const CfSpec& spec) {
  int nc = -1;
  check(nc_create(path.c_str(), spec.netcdf4 ? (NC_CLOBBER | NC_NETCDF4) : NC_CLOBBER, &nc));
  int dTime, dRange, dSweep, dStr;
  check(nc_def_dim(nc, "time", spec.unlimitedTime ? NC_UNLIMITED : 5, &dTime));
  check(nc_def_dim(nc, "range", 3, &dRange));
  check(nc_def_dim(nc, "sweep", 2, &dSweep));
  check(nc_def_dim(nc, "string_length", 8, &dStr));
  const char* conv = "CF/Radial";
  check(nc_put_att_text(nc, NC_GLOBAL, "Conventions", std::strlen(conv), conv));
  const char* tcs = "2001-02-03T04:05:06Z";
  check(nc_put_att_text(nc, NC_GLOBAL, "time_coverage_start", std::strlen(tcs), tcs));
  int vStart = -1, vEnd, vFixed, vMode, vAz, vEl, vRange = -1, vLat, vLon, vAlt, vDbz;
  if (spec.withStartIndex) check(nc_def_var(nc, "sweep_start_ray_index", NC_INT, 1, &dSweep, &vStart));
  check(nc_def_var(nc, "sweep_end_ray_index", NC_INT, 1, &dSweep, &vEnd));
  check(nc_def_var(nc, "fixed_angle", NC_FLOAT, 1, &dSweep, &vFixed));
  int modeDims[2] = {dSweep, dStr};
  check(nc_def_var(nc, "sweep_mode", NC_CHAR, 2, modeDims, &vMode));
  check(nc_def_var(nc, "azimuth", NC_FLOAT, 1, &dTime, &vAz));
  check(nc_def_var(nc, "elevation", NC_FLOAT, 1, &dTime, &vEl));
  if (spec.withRange) check(nc_def_var(nc, "range", NC_FLOAT, 1, &dRange, &vRange));
  check(nc_def_var(nc, "latitude", NC_DOUBLE, 0, nullptr, &vLat));
  check(nc_def_var(nc, "longitude", NC_DOUBLE, 0, nullptr, &vLon));
  check(nc_def_var(nc, "altitude", NC_DOUBLE, 0, nullptr, &vAlt));
  int fieldDims[2] = {dTime, dRange};
  check(nc_def_var(nc, "DBZ", NC_SHORT, 2, fieldDims, &vDbz));
  const float scale = 0.5f, offset = -10.0f;
  const short fill = -999;
  check(nc_put_att_float(nc, vDbz, "scale_factor", NC_FLOAT, 1, &scale));
  check(nc_put_att_float(nc, vDbz, "add_offset", NC_FLOAT, 1, &offset));
  check(nc_put_att_short(nc, vDbz, "_FillValue", NC_SHORT, 1, &fill));
  check(nc_put_att_text(nc, vDbz, "units", 3, "dBZ"));
  check(nc_enddef(nc));
  const int starts[2] = {0, 3}, ends[2] = {1, 4};
  const float fixed[2] = {1.5f, 0.5f};
  if (spec.withStartIndex) check(nc_put_var_int(nc, vStart, starts));
  check(nc_put_var_int(nc, vEnd, ends));
  check(nc_put_var_float(nc, vFixed, fixed));
  const char modes[16] = {'a', 'z', 'i', 'm', 'u', 't', 'h', '_', 's', 'e', 'c', 't', 'o', 'r', 0, 0};
  check(nc_put_var_text(nc, vMode, modes));
  float az[5] = {10.f, 11.f, 200.f, 359.5f, 0.5f};
  if (spec.nanAzimuth) az[1] = std::nanf("");
  const float el[5] = {1.5f, 1.5f, 1.0f, 0.5f, 0.5f};
  const std::size_t start0[1] = {0}, count5[1] = {5};
  check(nc_put_vara_float(nc, vAz, start0, count5, az));
  check(nc_put_vara_float(nc, vEl, start0, count5, el));
  const float range[3] = {150.f, 450.f, 750.f};
  if (spec.withRange) check(nc_put_var_float(nc, vRange, range));
  const double lat = 10.25, lon = 200.5, alt = 123.0;  // lon 200.5 -> -159.5
  check(nc_put_var_double(nc, vLat, &lat));
  check(nc_put_var_double(nc, vLon, &lon));
  check(nc_put_var_double(nc, vAlt, &alt));
  short raw[15];
  for (int r = 0; r < 5; ++r)
    for (int g = 0; g < 3; ++g) raw[r * 3 + g] = static_cast<short>(10 * r + g);
  raw[4 * 3 + 2] = fill;
  const std::size_t s2[2] = {0, 0}, c2[2] = {5, 3};
  check(nc_put_vara_short(nc, vDbz, s2, c2, raw));
  check(nc_close(nc));
}

// ---------------------------------------------------------------- synthetic ODIM
struct OdimSpec {
  double nbinsAttr = 3;  ///< what /dataset1/where/nbins says
  double nraysAttr = 4;
  std::size_t rays = 4, bins = 3;  ///< the data array's real shape
  bool nbinsAsText = false;
  std::string source = "NOD:xxtst";  ///< /what/source
};

void putDouble(int g, const char* name, double v) { check(nc_put_att_double(g, NC_GLOBAL, name, NC_DOUBLE, 1, &v)); }
void putText(int g, const char* name, const char* v) { check(nc_put_att_text(g, NC_GLOBAL, name, std::strlen(v), v)); }

/// One PVOL sweep at 0.5 deg, DBZH uint8 gain 0.5 offset -32 nodata 255 undetect 0;
/// raw = 1 + ray * 10 + bin except raw(0,0) = 255 (nodata) and raw(1,1) = 0 (undetect).
void writeOdim(const std::string& path, const OdimSpec& spec) {
  int nc = -1;
  check(nc_create(path.c_str(), NC_CLOBBER | NC_NETCDF4, &nc));
  putText(nc, "Conventions", "ODIM_H5/V2_2");
  int what, where, ds, dsWhere, data, dataWhat;
  check(nc_def_grp(nc, "what", &what));
  putText(what, "object", "PVOL");
  putText(what, "date", "20200102");
  putText(what, "time", "030405");
  putText(what, "source", spec.source.c_str());
  check(nc_def_grp(nc, "where", &where));
  putDouble(where, "lat", -45.5);
  putDouble(where, "lon", 170.25);
  putDouble(where, "height", 321.0);
  check(nc_def_grp(nc, "dataset1", &ds));
  check(nc_def_grp(ds, "where", &dsWhere));
  putDouble(dsWhere, "elangle", 0.5);
  if (spec.nbinsAsText) putText(dsWhere, "nbins", "3");
  else putDouble(dsWhere, "nbins", spec.nbinsAttr);
  putDouble(dsWhere, "nrays", spec.nraysAttr);
  putDouble(dsWhere, "rstart", 2.0);
  putDouble(dsWhere, "rscale", 1000.0);
  putDouble(dsWhere, "a1gate", 2.0);
  check(nc_def_grp(ds, "data1", &data));
  check(nc_def_grp(data, "what", &dataWhat));
  putText(dataWhat, "quantity", "DBZH");
  putDouble(dataWhat, "gain", 0.5);
  putDouble(dataWhat, "offset", -32.0);
  putDouble(dataWhat, "nodata", 255.0);
  putDouble(dataWhat, "undetect", 0.0);
  int dRay, dBin, var;
  check(nc_def_dim(data, "phony_dim_0", spec.rays, &dRay));
  check(nc_def_dim(data, "phony_dim_1", spec.bins, &dBin));
  int dims[2] = {dRay, dBin};
  check(nc_def_var(data, "data", NC_UBYTE, 2, dims, &var));
  if (spec.rays * spec.bins > 1000) {
    // Huge dataspace with nothing written: chunked + deflated, so the file stays tiny.
    std::size_t chunk[2] = {1, std::min<std::size_t>(spec.bins, 1000)};
    check(nc_def_var_chunking(data, var, NC_CHUNKED, chunk));
    check(nc_def_var_deflate(data, var, 0, 1, 1));
    check(nc_close(nc));
    return;
  }
  check(nc_enddef(nc));
  std::vector<unsigned char> raw(spec.rays * spec.bins);
  for (std::size_t r = 0; r < spec.rays; ++r)
    for (std::size_t b = 0; b < spec.bins; ++b) raw[r * spec.bins + b] = static_cast<unsigned char>(1 + r * 10 + b);
  raw[0] = 255;
  if (spec.rays > 1 && spec.bins > 1) raw[spec.bins + 1] = 0;
  check(nc_put_var_uchar(data, var, raw.data()));
  check(nc_close(nc));
}

void writeBytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// The error from readRadarVolume (expects failure), checked to name the file.
std::string expectError(const std::string& path, const ReadOptions& o = {}) {
  auto r = readRadarVolume(path, o);
  EXPECT_FALSE(r.ok()) << path << " was read without error";
  if (r.ok()) return {};
  EXPECT_NE(r.error().find(path), std::string::npos) << "message does not name the file: " << r.error();
  return r.error();
}

bool mentions(const std::string& msg, const char* what) { return msg.find(what) != std::string::npos; }

}  // namespace

TEST(BadInput, ValidSyntheticCfRadialReadsCorrectly) {
  for (bool nc4 : {false, true}) {
    const std::string p = outDir() + (nc4 ? "/good_cf4.nc" : "/good_cf3.nc");
    CfSpec spec;
    spec.netcdf4 = nc4;
    writeCfRadial(p, spec);
    EXPECT_EQ(detectRadarFormat(p).value(), RadarFormat::CfRadial);
    auto r = readRadarVolume(p, {});
    ASSERT_TRUE(r.ok()) << r.error();
    const RadarVolume& v = *r;
    ASSERT_EQ(v.sweeps.size(), 2u);
    // Sorted by fixed angle: file sweep 1 (0.5 deg, rays 3-4) first; ray 2 dropped.
    EXPECT_EQ(v.sweeps[0].indexInFile, 1);
    EXPECT_FLOAT_EQ(static_cast<float>(v.sweeps[0].fixedAngleDeg), 0.5f);
    EXPECT_EQ(v.sweeps[0].rayCount(), 2u);
    EXPECT_EQ(v.sweeps[1].rayCount(), 2u);
    EXPECT_FLOAT_EQ(v.sweeps[0].azimuthDeg[0], 359.5f);
    EXPECT_DOUBLE_EQ(v.sweeps[0].firstGateRangeMeters, 150.0);
    EXPECT_DOUBLE_EQ(v.sweeps[0].gateSpacingMeters, 300.0);
    EXPECT_DOUBLE_EQ(v.site.lonDeg, -159.5);
    EXPECT_EQ(v.timeIso8601, "2001-02-03T04:05:06Z");
    // raw 10*ray + gate -> 0.5 * raw - 10 (exact in binary)
    EXPECT_FLOAT_EQ(v.sweeps[1].value(1, 2), 0.5f * 12 - 10);  // file ray 1, gate 2
    EXPECT_FLOAT_EQ(v.sweeps[0].value(0, 1), 0.5f * 31 - 10);  // file ray 3, gate 1
    EXPECT_TRUE(isNoData(v.sweeps[0].value(1, 2)));            // file ray 4, gate 2: _FillValue
  }
}

TEST(BadInput, ValidSyntheticOdimReadsCorrectly) {
  const std::string p = outDir() + "/good_odim.h5";
  writeOdim(p, {});
  EXPECT_EQ(detectRadarFormat(p).value(), RadarFormat::OdimH5);
  auto r = readRadarVolume(p, {});
  ASSERT_TRUE(r.ok()) << r.error();
  ASSERT_EQ(r->sweeps.size(), 1u);
  const Sweep& s = r->sweeps[0];
  EXPECT_EQ(s.rayCount(), 4u);
  EXPECT_EQ(s.gateCount, 3u);
  EXPECT_DOUBLE_EQ(s.firstGateRangeMeters, 2500.0);  // rstart 2 km + 1000 m / 2
  EXPECT_FLOAT_EQ(s.azimuthDeg[1], 135.0f);          // (1 + 0.5) * 90
  EXPECT_TRUE(isNoData(s.value(0, 0)));
  EXPECT_TRUE(isNoEcho(s.value(1, 1)));
  EXPECT_FLOAT_EQ(s.value(3, 2), 0.5f * (1 + 30 + 2) - 32);
  EXPECT_EQ(r->site.name, "xxtst");
}

TEST(BadInput, EmptyFile) {
  const std::string p = outDir() + "/empty.nc";
  writeBytes(p, {});
  const std::string e = expectError(p);
  EXPECT_TRUE(mentions(e, "empty")) << e;
}

TEST(BadInput, RandomBytes) {
  const std::string p = outDir() + "/random.h5";
  std::mt19937 rng(12345);
  std::vector<char> bytes(65536);
  for (char& c : bytes) c = static_cast<char>(rng() & 0xff);
  writeBytes(p, bytes);
  const std::string e = expectError(p);
  EXPECT_TRUE(mentions(e, "not a CfRadial, ODIM_H5 or NEXRAD Level II file")) << e;
}

TEST(BadInput, TextFileNamedH5) {
  const std::string p = outDir() + "/notes.h5";
  const std::string text = "This is not radar data.\nJust a text file with an .h5 name.\n";
  writeBytes(p, std::vector<char>(text.begin(), text.end()));
  const std::string e = expectError(p);
  EXPECT_TRUE(mentions(e, "not a CfRadial, ODIM_H5 or NEXRAD Level II file")) << e;
  // The direct readers also refuse it, naming the file.
  auto c = readCfRadial(p, {});
  ASSERT_FALSE(c.ok());
  EXPECT_TRUE(mentions(c.error(), p.c_str())) << c.error();
  auto o = readOdimH5(p, {});
  ASSERT_FALSE(o.ok());
  EXPECT_TRUE(mentions(o.error(), p.c_str())) << o.error();
}

TEST(BadInput, TruncatedRealFiles) {
  for (const std::string& src :
       {kData + "/radar_cfradial/example_plot_ppi_single_sweep.nc", kData + "/radar_cfradial/MLL2217907250U.003.nc",
        kData + "/radar_cfradial/cfrad.20211011_201733.023_to_20211011_201745.299_DOW8_RHI.nc",
        kData + "/radar_odim/40_20181220_060630.pvol.h5", kData + "/radar_odim/bewid.pvol.hdf",
        kData + "/radar_sigmet/SUR210819000227.RAWKPJV", kData + "/radar_rainbow/2013051000000600dBZ.vol"}) {
    SKIP_WITHOUT_TEST_DATA(src);
    std::ifstream in(src, std::ios::binary);
    std::vector<char> head(4096);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    ASSERT_EQ(in.gcount(), 4096);
    const std::string p = outDir() + "/truncated_" + std::filesystem::path(src).filename().string();
    writeBytes(p, head);
    expectError(p);
    ReadOptions meta;
    meta.loadValues = false;
    expectError(p, meta);
  }
}

TEST(BadInput, CfRadialMissingSweepStartRayIndex) {
  const std::string p = outDir() + "/no_start_index.nc";
  CfSpec spec;
  spec.withStartIndex = false;
  writeCfRadial(p, spec);
  // Detected as CfRadial only through the magic bytes (classic) - the reader says what is missing.
  const std::string e = expectError(p);
  EXPECT_TRUE(mentions(e, "sweep_start_ray_index")) << e;
}

TEST(BadInput, CfRadialMissingRange) {
  for (bool nc4 : {false, true}) {
    const std::string p = outDir() + (nc4 ? "/no_range4.nc" : "/no_range3.nc");
    CfSpec spec;
    spec.withRange = false;
    spec.netcdf4 = nc4;
    writeCfRadial(p, spec);
    const std::string e = expectError(p);
    EXPECT_TRUE(mentions(e, "'/range'")) << e;
  }
}

TEST(BadInput, CfRadialNanAzimuth) {
  const std::string p = outDir() + "/nan_azimuth.nc";
  CfSpec spec;
  spec.nanAzimuth = true;
  writeCfRadial(p, spec);
  const std::string e = expectError(p);
  EXPECT_TRUE(mentions(e, "ray 1")) << e;
  EXPECT_TRUE(mentions(e, "azimuth")) << e;
}

TEST(BadInput, CfRadialRecordCountClaimingBillions) {
  // Classic file with time as the record dimension; patch numrecs (bytes 4-7, big-endian,
  // CDF-1) to 2e9 records: the header then claims 2e9 rays in a file of a few hundred bytes.
  const std::string p = outDir() + "/huge_numrecs.nc";
  CfSpec spec;
  spec.unlimitedTime = true;
  writeCfRadial(p, spec);
  {
    std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
    const unsigned char numrecs[4] = {0x77, 0x35, 0x94, 0x00};  // 2,000,000,000
    f.seekp(4);
    f.write(reinterpret_cast<const char*>(numrecs), 4);
  }
  expectError(p);
}

// The site's name from /what/source (ODIM_H5 2.2, Table 3: comma-separated KEY:value pairs): the
// node (NOD) first, then the radar (RAD), the place (PLC), the WMO number. Some writers separate the
// pairs with ';': the name is still one value, never the whole string.
// The place (PLC) is kept beside the name, and titles show both (siteTitle).
TEST(BadInput, OdimSiteNameIsOneValueOfTheSource) {
  struct Case {
    const char *source, *name, *place, *title;
  };
  const Case cases[] = {
      {"WMO:06234,RAD:NL51,PLC:Den Helder,NOD:nldhl", "nldhl", "Den Helder", "nldhl (Den Helder)"},
      {"RAD:NL51;PLC:nldhl", "NL51", "nldhl", "NL51 (nldhl)"},
      {"WMO:06475", "06475", "", "06475"},
      {"PLC:Den Helder,WMO:06234", "Den Helder", "", "Den Helder"},
  };
  for (const Case& c : cases) {
    const std::string p = outDir() + "/odim_source.h5";
    OdimSpec spec;
    spec.source = c.source;
    writeOdim(p, spec);
    auto r = readRadarVolume(p, {});
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r->site.name, c.name) << c.source;
    EXPECT_EQ(r->site.placeName, c.place) << c.source;
    EXPECT_EQ(siteTitle(r->site), c.title) << c.source;
  }
}

TEST(BadInput, OdimNbinsClaimingTwoBillion) {
  const std::string p = outDir() + "/nbins_2e9.h5";
  OdimSpec spec;
  spec.nbinsAttr = 2e9;
  writeOdim(p, spec);
  const std::string e = expectError(p);
  EXPECT_TRUE(mentions(e, "nbins")) << e;
  ReadOptions meta;
  meta.loadValues = false;  // even the metadata-only read (atmoglobe info) refuses it
  const std::string e2 = expectError(p, meta);
  EXPECT_TRUE(mentions(e2, "nbins")) << e2;
}

TEST(BadInput, OdimNbinsDisagreeingWithTheArray) {
  const std::string p = outDir() + "/nbins_wrong.h5";
  OdimSpec spec;
  spec.nbinsAttr = 4;  // array is 4 x 3
  writeOdim(p, spec);
  const std::string e = expectError(p);
  EXPECT_TRUE(mentions(e, "nbins = 4")) << e;
  EXPECT_TRUE(mentions(e, "4 x 3")) << e;
}

TEST(BadInput, OdimZeroRaysAndTextNbins) {
  const std::string p = outDir() + "/nrays_zero.h5";
  OdimSpec spec;
  spec.nraysAttr = 0;
  writeOdim(p, spec);
  std::string e = expectError(p);
  EXPECT_TRUE(mentions(e, "nrays")) << e;
  const std::string q = outDir() + "/nbins_text.h5";
  OdimSpec spec2;
  spec2.nbinsAsText = true;
  writeOdim(q, spec2);
  e = expectError(q);
  EXPECT_TRUE(mentions(e, "nbins")) << e;
  EXPECT_TRUE(mentions(e, "not numeric")) << e;
}

TEST(BadInput, OdimDataspaceClaimingHundredBillionGates) {
  // Attributes and array agree on 100000 rays x 1000000 bins (1e11 bytes) but nothing is
  // stored: a metadata read works, decoding refuses before allocating.
  const std::string p = outDir() + "/huge_dataspace.h5";
  OdimSpec spec;
  spec.nraysAttr = 100000;
  spec.nbinsAttr = 1000000;
  spec.rays = 100000;
  spec.bins = 1000000;
  writeOdim(p, spec);
  ASSERT_LT(std::filesystem::file_size(p), 1u << 20);
  ReadOptions meta;
  meta.loadValues = false;
  auto ok = readRadarVolume(p, meta);
  ASSERT_TRUE(ok.ok()) << ok.error();
  EXPECT_EQ(ok->sweeps[0].gateCount, 1000000u);
  const std::string e = expectError(p);
  EXPECT_TRUE(mentions(e, "claims")) << e;
}
