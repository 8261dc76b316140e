#pragma once
// GSHHG coastlines and WDBII political borders from GMT's binned NetCDF files (Debian
// `gmt-gshhg`: /usr/share/gmt-gshhg/binned_{GSHHS,border}_{c,l,i,h,f}.nc). GL-free.
//
// The binned layout (read with `ncdump -h`): the globe is cut into square bins of
// Bin_size_in_minutes (c 20 deg, l 10, i 5, h 2, f 1), numbered row by row from the north-west
// corner (bin b: column b % N_bins_in_360_longitude_range from longitude 0 eastwards, row
// b / that from latitude 90 southwards). Each bin lists its segments (Id_of_first_segment_in_a_bin,
// N_segments_in_a_bin), each segment its points (Id_of_first_point_in_a_segment and a count),
// and each point is two unsigned 16-bit offsets from the bin's south-west corner in units of
// bin size / 65535. Shoreline segments pack their point count, level and bin-edge entry/exit
// into Embedded_npts_levels_exit_entry_for_a_segment (count = value >> 9, level = (value >> 6)
// & 7); border segments carry N_points_for_a_segment and Hierarchial_level_of_a_segment. Only
// the bins asked for are read from the file.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/map/GeoLines.h>

#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::map {

/// The five GSHHG resolutions, coarsest first (the letter in the file names).
enum class GshhgResolution { Crude = 0, Low, Intermediate, High, Full };
char gshhgResolutionLetter(GshhgResolution r);

/// What a binned file holds.
enum class GshhgKind { Shoreline, Border };

/// Levels of the two kinds (a level mask takes 1 << level).
/// Shorelines: 1 land/ocean coast, 2 lake shore, 3 island in a lake, 4 pond on such an island.
/// Borders: 1 national boundaries, 2 internal (states, provinces), 3 marine boundaries.
inline constexpr unsigned kCoastLevels = 1u << 1 | 1u << 2;
inline constexpr unsigned kNationalBorderLevels = 1u << 1;
inline constexpr unsigned kStateBorderLevels = 1u << 2;

/// $ATMOGLOBE_GSHHG_DIR when set, else the build's default (/usr/share/gmt-gshhg).
std::string defaultGshhgDirectory();
/// dir/binned_GSHHS_c.nc, dir/binned_border_f.nc, ...
std::string gshhgPath(const std::string& dir, GshhgKind kind, GshhgResolution resolution);

/// A bin's box (degrees; west in [-180, 180), east = west + size).
struct GshhgBinBox {
  double westDeg, southDeg, eastDeg, northDeg;
};

class GshhgFile {
 public:
  /// Opens the file and reads its bin tables (small). Errors name the file and the problem.
  static Result<std::unique_ptr<GshhgFile>> open(const std::string& path, GshhgKind kind);
  ~GshhgFile();
  GshhgFile(const GshhgFile&) = delete;
  GshhgFile& operator=(const GshhgFile&) = delete;

  int binCount() const { return static_cast<int>(firstSegment_.size()); }
  double binSizeDeg() const { return binSizeDeg_; }
  GshhgBinBox binBox(int bin) const;
  /// Bins overlapping [west, east] x [south, north] (degrees; west > east crosses the antimeridian).
  std::vector<int> binsOverlapping(double westDeg, double southDeg, double eastDeg, double northDeg) const;
  /// The bins inside `box`, a box of whole bins of this file (the whole globe, or a coarser
  /// file's bin: 20-degree bins hold whole 10, 5, 2 and 1-degree ones, 10-degree bins 5, 2 and 1),
  /// by index arithmetic: binsOverlapping scans every bin (64,800 at the full level).
  std::vector<int> binsInside(const GshhgBinBox& box) const;
  /// The segments of `bin` whose level is in `levelMask` (1 << level), as polylines in
  /// [-180, 180] longitudes.
  Result<std::vector<GeoPolyline>> readBin(int bin, unsigned levelMask) const;
  const std::string& path() const { return path_; }

 private:
  GshhgFile() = default;
  std::string path_;
  GshhgKind kind_ = GshhgKind::Shoreline;
  int ncid_ = -1;
  int binsAcross_ = 0;
  double binSizeDeg_ = 0.0;
  long long pointCount_ = 0, segmentCount_ = 0;
  std::vector<int> firstSegment_;
  std::vector<int> segmentsInBin_;
  int varSegInfo_ = -1, varSegLevel_ = -1, varSegCount_ = -1, varSegFirstPoint_ = -1, varLon_ = -1, varLat_ = -1;
};

}  // namespace atmoglobe::map
