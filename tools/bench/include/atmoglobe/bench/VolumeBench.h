#pragma once
// `atmoglobe bench`: the speed/accuracy trade of the GPU volume marcher, measured for radar
// volumes (docs/bench-volume.md) and forecast grids (docs/grids.md "Benchmark"). Fixed views of
// real volumes (Views.h, GridViews.h); a grid of step x image scale x
// interpolation x beam model (DVR; MIP and ISO at the default; Cells.h); per cell the median GPU
// frame time and the error against the CPU reference renderer (Measure.h, ReferenceCache.h).
// Then the side-by-side peer (VtkPeer.h), and the report (Report.h) under the output directory.
#include <atmoglobe/globe/Result.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace atmoglobe::bench {

struct VolumeBenchOptions {
  std::string dataDir = "../shared/data";  ///< holds radar_nexrad/ and radar_odim/
  std::string outDir = "out/bench";
  bool quick = false;  ///< KLBB oblique only, a small grid, 160x90
  int frames = 7;      ///< timed frames per cell (median)
  /// The settings grid's image size (the peer's too); 0: 320x180 (quick 160x90).
  int widthPx = 0, heightPx = 0;
  double referenceStepMeters = 100.0;
  int threads = 0;  ///< reference and resampling threads; 0: hardware concurrency
  bool peer = true;
  bool referenceOnly = false;          ///< only fill the reference cache (no GL)
  std::string peerScript;              ///< empty: found (VtkPeer.h findPeerScript)
  std::vector<std::string> viewNames;  ///< empty: every view
  std::vector<double> stepsMeters;     ///< empty: the standard grid

  // --- forecast grids ( docs/grids.md "Benchmark") ---
  bool grids = false;        ///< the grid bench: the built-in synthetic grids, or gridFile
  std::string gridFile;      ///< a grid file instead of the built-in ones
  std::string gridVariable;  ///< with gridFile; empty: the reader's default
  std::size_t gridTimeIndex = 0;
  long gridMember = -1;               ///< with gridFile: the ensemble member; -1: the first
  int loadRuns = 5;                   ///< timed runs per load case (median), each case in a child process
  bool load = true;                   ///< measure the load cases
  bool big = true;                    ///< frames and errors at 1280x720 too
  double gridPeerMaxVoxels = 1.35e8;  ///< the peer's Cartesian grid cap for grids (540 MB float32; quick 3.2e7)
  std::string selfExe;                ///< the executable the load probes run (`--load-probe`); empty: /proc/self/exe
};

struct VolumeBenchOutcome {
  std::vector<std::string> files;  ///< the report files written (none with referenceOnly)
  std::string peerNote;            ///< why the peer was skipped or what failed; empty: nothing to say
};

/// Runs the bench, progress on `log`: radar volumes, or forecast grids (options.grids or
/// options.gridFile; per grid the load cases, GridLoad.h, and views that each draw their crop,
/// occluded by the ellipsoid, GridViews.h). One loop for every kind: per view the settings grid
/// at the bench size against the reference, then 1280x720 (grids: a DVR subset against the
/// reference at that size; radars: the default timed), the convergence of the reference, the VTK
/// peer, and the report (volume_bench.* or grid_bench.*). Errors: an unknown view name (checked before anything is
/// loaded), a volume that cannot be loaded, no GL context, a file that cannot be written.
Result<VolumeBenchOutcome> runVolumeBench(const VolumeBenchOptions& options, std::ostream& log);

}  // namespace atmoglobe::bench
