#pragma once
// The scene-load bench (`atmoglobe bench --scenes`, docs/scene-load.md): load time, peak memory
// and frame time of scenes of 1, 4 and 16 radar volumes, 1 and 10 time steps, a whole-globe
// and a regional view, to show that cost follows what the view shows, not what the files hold.
//
// Data: SYNTHETIC CfRadial volumes (SyntheticRadar.h: VCP 212, 360 rays, 500 m gates to 230 km) at 16 NEXRAD sites
// (positions from a station list in DATA/stations when there is one, else built in), 10 times
// each (a loop directory per site), written once under OUT/scenes/data.
// Each case runs in a fresh child process (`atmoglobe bench --scene-probe JOB RESULT`, no
// shell) so its peak memory (ru_maxrss from wait4) is its own; medians over `runs` children.
#include <atmoglobe/globe/Result.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace atmoglobe::bench {

struct SceneBenchOptions {
  std::string dataDir = "../shared/data";
  std::string outDir = "out/bench";
  int runs = 3;    ///< children per case (median)
  int frames = 3;  ///< timed frames per child (median)
  int widthPx = 480, heightPx = 270;
  std::string selfExe;  ///< empty: /proc/self/exe
};

struct SceneCaseResult {
  std::string name, view;
  int radars = 0, steps = 0;
  bool cull = true;
  int loaded = 0;          ///< radars loaded (after culling)
  double fileMb = 0.0;     ///< bytes on disk of every file the scene names (all steps)
  double readMb = 0.0;     ///< variable data read through netCDF (NetcdfFile tally)
  double loadMs = 0.0;     ///< cull + read + layout + GPU upload (median)
  double frameMs = 0.0;    ///< renderToImage (median)
  double stepMs = 0.0;     ///< time series: change of step + frame (median), else 0
  double peakRssMb = 0.0;  ///< ru_maxrss of the child (median)
  std::string error;
};

Result<std::vector<SceneCaseResult>> runSceneBench(const SceneBenchOptions& options, std::ostream& log);

/// The child: job JSON {"radars": [paths], "camera": [lat, lon, h, heading, pitch, roll],
/// "fov", "width", "height", "frames", "cull", "steps"}; writes the result JSON. Exit status.
int runSceneProbe(const std::string& jobFile, const std::string& resultFile);

/// The table in markdown (docs/scene-load.md).
std::string sceneBenchMarkdown(const std::vector<SceneCaseResult>& results, const SceneBenchOptions& options);

}  // namespace atmoglobe::bench
