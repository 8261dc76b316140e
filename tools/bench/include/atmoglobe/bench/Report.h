#pragma once
// The bench's results and their writers, apart from the measuring: volume_bench.md (tables),
// volume_bench.csv (one row per view x cell), volume_bench.png (error against frame time, log
// time axis, Pareto front, default ringed). docs/bench-volume.md describes the format.
#include <atmoglobe/bench/Cells.h>
#include <atmoglobe/bench/GridLoad.h>
#include <atmoglobe/bench/Views.h>
#include <atmoglobe/bench/VtkPeer.h>
#include <atmoglobe/engine/PlotImage.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/VolumeImage.h>

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace atmoglobe::bench {

/// One view x one cell.
struct Row {
  std::string view;
  std::string volume;
  Cell cell;
  int widthPx = 0, heightPx = 0;
  double medianMs = 0.0;
  volume::ImageError error;
  std::size_t gpuBytes = 0;  ///< the GPU volume drawn (a grid view: its crop)
  /// Grids: the level of detail marched (volume/GridDetail.h; 0: the grid itself). Rows of a
  /// level > 0 are BenchReport::detailRows, never among the settings' rows.
  int detailLevel = 0;
  /// Detail rows at a size of a quarter of 1280x720 or less: the error against the reference
  /// rendered with 4 x 4 rays a pixel and averaged (what the pixel covers, not one ray through
  /// it), where a coarser copy may be closer than the grid itself.
  std::optional<volume::ImageError> pixelAverageError;
};

/// One cell over the views.
struct Aggregate {
  Cell cell;
  double meanMs = 0.0;      ///< mean over views of the median frame time
  double meanAbs = 0.0;     ///< mean over views
  double maxAbs = 0.0;      ///< max over views
  double meanPsnrDb = 0.0;  ///< mean over views (each capped at 99 dB: identical images are +inf)
  double minPsnrDb = 0.0;
  bool pareto = false;  ///< DVR only: no other DVR cell is at least as fast and as accurate
};

/// Per cell of `cells` that has rows (in the order of `cells`), with the Pareto front among DVR
/// cells: no other cell is at least as fast and at least as accurate (mean abs error) and
/// strictly better in one.
std::vector<Aggregate> aggregate(const std::vector<Row>& rows, const std::vector<Cell>& cells);

struct VolumeSummary {
  std::string key, path, fieldName;
  std::size_t sweeps = 0;
  std::size_t gpuBytes = 0;
  double cartesianBytes = 0.0;  ///< volume::cartesianEquivalentBytes at float32
};

struct BigTiming {  ///< the default setting at 1280x720, time only
  std::string view;
  double ms = 0.0;
};

struct Convergence {  ///< the reference step against half of it
  std::string view;
  volume::ImageError error;
};

struct BenchReport {
  std::string kind = "radar";  ///< "radar": volume_bench.*; "grid": grid_bench.*
  std::string machine;         ///< machineLine()
  int widthPx = 0, heightPx = 0;
  int frames = 0;
  double referenceStepMeters = 0.0;
  std::vector<VolumeSummary> volumes;
  std::vector<BenchView> views;  ///< name, pose, fovY (the volume pointer is not used)
  // References.
  int referencesRendered = 0, referencesCached = 0, referenceThreads = 0;
  double referenceSeconds = 0.0;
  std::string referenceCacheDir;
  std::vector<Convergence> convergence;
  std::vector<Row> rows;
  std::vector<Aggregate> aggregates;
  std::vector<BigTiming> big;
  std::vector<Row> bigRows;  ///< grids: 1280x720 cells with their error
  /// Grids: the default setting at the level of detail the engine picks for the view and size,
  /// where that is not the grid itself (error against the same reference as the other rows).
  std::vector<Row> detailRows;
  std::vector<LoadCase> loads;  ///< grids: the load cases
  PeerSection peer;
  double totalSeconds = 0.0;
};

/// "CPU: <model name>, N hardware threads; GL: <gl>".
std::string machineLine(const std::string& gl);

void writeCsv(std::ostream& out, const std::vector<Row>& rows);
void writeMarkdown(std::ostream& out, const BenchReport& report);
/// The grid bench's markdown: load table, per-view settings at both sizes, the peer against ours
/// at equal or lower error (time and memory ratios), the target verdict per view.
void writeGridMarkdown(std::ostream& out, const BenchReport& report);

/// Ours against one peer run: the fastest of `rows` (same view and size) whose mean abs error is
/// at most the peer's. Null when none is.
const Row* fastestAtOrBelowError(const std::vector<Row>& rows, const std::string& view, double meanAbs);
/// The error-vs-time plot of the DVR aggregates.
engine::ScatterPlot errorTimePlot(const BenchReport& report);

/// The report's three files in `outDir` (volume_bench.* or, for grids, grid_bench.*), their
/// paths in `written` (md, csv, png). Errors name the file.
Status writeReport(const std::string& outDir, const BenchReport& report, std::vector<std::string>* written);

}  // namespace atmoglobe::bench
