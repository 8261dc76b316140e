#pragma once
// The side-by-side peer: each volume resampled to a Cartesian grid (PeerGrid.h) and rendered by
// VTK (tools/bench/vtk_peer.py under xvfb-run, run without a shell: Process.h) with the same
// cameras and transfer function; its frames timed by the script, its images compared with the
// same references.
#include <atmoglobe/bench/PeerGrid.h>
#include <atmoglobe/bench/ReferenceCache.h>
#include <atmoglobe/bench/Views.h>
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/VolumeImage.h>

#include <filesystem>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace atmoglobe::bench {

struct PeerResult {
  std::string view, mapper;
  double medianMs = 0.0;
  double peakRssMb = 0.0;
  volume::ImageError error;
  bool ok = false;  ///< the image was read and compared
  std::string note;
};

/// What the peer produced for the report.
struct PeerSection {
  std::string note;                       ///< why it was skipped or what failed; empty: nothing to say
  std::map<std::string, PeerGrid> grids;  ///< by volume key (the grid each VTK run was given)
  std::vector<PeerResult> results;
};

/// The script: `explicitPath` when given, else tools/bench/vtk_peer.py from the working
/// directory or from a directory above the executable; "" when none exists.
std::string findPeerScript(const std::string& explicitPath);

/// Empty when the peer can run (python3 can `import vtk`, xvfb-run is in PATH, `script` is not
/// empty); else the reason, as the report prints it ("python3-vtk9 is not installed", ...).
std::string peerUnavailableReason(const std::string& script);

struct PeerSettings {
  std::filesystem::path outDir;  ///< the peer's files go to outDir/peer/
  std::string script;            ///< vtk_peer.py
  int widthPx = 0, heightPx = 0, frames = 1;
  double maxVoxels = 2.7e8;  ///< the grid's voxel cap (3.2e7 for --quick)
  int threads = 1;           ///< for the resampling
  double referenceStepMeters = 100.0;
};

/// Runs the peer for every volume with at least one of `views`: resample, write the grid and a
/// job, run the script, read its result, compare its images with `refs` (DVR references at the
/// same size). Skipped (with the reason in the note, nothing run) when peerUnavailableReason
/// says so. A script that fails is a note (the runs that finished before are kept, the script
/// rewrites its result after each); the error is only for a grid that cannot be written.
Result<PeerSection> runVtkPeer(const std::vector<std::unique_ptr<BenchVolume>>& volumes,
                               const std::vector<BenchView>& views, const PeerSettings& settings, ReferenceStore& refs,
                               std::ostream& log);

}  // namespace atmoglobe::bench
