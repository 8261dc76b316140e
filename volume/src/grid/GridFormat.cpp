// Which files are forecast grids (GRIB by its signature, netCDF by its content), in what format (CF or WRF, and the
// container), and which variable is read when none is named.
#include "GribInternal.h"
#include "GridInternal.h"

#include <atmoglobe/volume/GridReader.h>

namespace atmoglobe::volume {

namespace grid {

FileKind fileKind(const io::NetcdfFile& f) {
  FileKind k;
  const std::string title = globalText(f, "TITLE");
  const int root = f.root();
  k.wrf = title.find("WRF") != std::string::npos ||
          (f.findVariable(root, "XLAT") && f.findVariable(root, "XLONG") && f.dimensionLength(root, "bottom_top") &&
           f.dimensionLength(root, "west_east"));
  k.conventions = k.wrf ? (title.empty() ? std::string("WRF") : title) : globalText(f, "Conventions");
  while (!k.conventions.empty() && k.conventions.front() == ' ') k.conventions.erase(k.conventions.begin());
  int fmt = 0;
  {
    const io::NetcdfLock lock;
    nc_inq_format(root, &fmt);
  }
  const char* container = fmt == NC_FORMAT_NETCDF4           ? "netCDF-4"
                          : fmt == NC_FORMAT_NETCDF4_CLASSIC ? "netCDF-4 classic model"
                          : fmt == NC_FORMAT_64BIT_OFFSET    ? "netCDF 64-bit offset"
                          : fmt == NC_FORMAT_CDF5            ? "netCDF CDF5"
                                                             : "netCDF classic";
  const bool cf = k.conventions.find("CF") != std::string::npos || k.conventions.find("COARDS") != std::string::npos;
  k.format = std::string(k.wrf ? "WRF" : cf ? "CF" : "netCDF grid").append(" (").append(container).append(")");
  return k;
}

Result<GridLayout> layoutFor(const io::NetcdfFile& f, const FileKind& kind, const std::string& variable,
                             std::string* chosen, bool allowSingleLevel) {
  if (!variable.empty()) {
    auto v = findGridVariable(f, variable);
    if (!v) return v.forwardError();
    *chosen = v->name;
    return analyse(f, kind, *v, allowSingleLevel);
  }
  const std::vector<GridVariableInfo> vars = listVariables(f, kind);
  const std::string name = chooseDefaultGridVariable(vars);
  if (name.empty()) {
    // Say why the first of the variables with the most dimensions (three or more) is not a grid
    // variable: a (time, level, y, x) field says more than a (time, y, x) one.
    std::optional<io::NcVar> first;
    for (int g : allGroups(f))
      for (const io::NcVar& v : f.variables(g))
        if (v.dimIds.size() >= 3 && io::ncTypeIsNumeric(v.type) && (!first || v.dimIds.size() > first->dimIds.size()))
          first = v;
    if (first)
      if (auto why = analyse(f, kind, *first); !why)
        return makeError(why.error() + " (no variable of the file is a 3-D grid this reader can read)");
    return makeError(
        f.message("no variable with a vertical and two horizontal dimensions (latitude/longitude "
                  "coordinates) found: not a forecast grid"));
  }
  auto v = findGridVariable(f, name);
  if (!v) return v.forwardError();
  *chosen = v->name;
  return analyse(f, kind, *v);
}

}  // namespace grid

std::string chooseDefaultGridVariable(const std::vector<GridVariableInfo>& variables) {
  auto shortName = [](const std::string& n) { return n.substr(n.rfind('/') + 1); };
  for (const char* want : {"REFL_10CM", "dbz", "DBZ", "reflectivity", "QCLOUD", "QRAIN", "clw", "cloud_water"})
    for (const auto& v : variables)
      if (v.onGrid && shortName(v.name) == want) return v.name;
  for (const char* want : {"equivalent_reflectivity_factor", "mass_fraction_of_cloud_liquid_water_in_air",
                           "cloud_liquid_water_mixing_ratio"})
    for (const auto& v : variables)
      if (v.onGrid && v.standardName == want) return v.name;
  for (const auto& v : variables)
    if (v.onGrid) return v.name;
  return {};
}

bool isGridFile(const std::string& path) {
  // Every GRIB file or set of GRIB files: `info` lists what it holds.
  if (grib::hasGribSignature(path) || grib::isGribSet(path)) return true;
  if (!io::hasNetcdfSignature(path)) return false;
  auto f = io::NetcdfFile::open(path);
  if (!f) return false;
  const int root = f->root();
  // Radar marks first: a CfRadial or ODIM file is not a grid even if it has 3-D variables.
  if (f->findVariable(root, "sweep_start_ray_index")) return false;
  const std::string conventions = grid::globalText(*f, "Conventions");
  if (conventions.rfind("ODIM_H5", 0) == 0 || conventions.find("Radial") != std::string::npos) return false;
  const grid::FileKind kind = grid::fileKind(*f);
  if (kind.wrf) return true;
  for (const GridVariableInfo& v : grid::listVariables(*f, kind))
    if (v.onGrid) return true;
  return false;
}

}  // namespace atmoglobe::volume
