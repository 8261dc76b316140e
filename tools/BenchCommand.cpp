// `atmoglobe bench`: the volume marcher's speed/accuracy trade against the CPU reference, with the
// VTK peer (docs/bench-volume.md). Option parsing only: the bench is the atmoglobe::bench library
// (tools/bench/README.md).
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/bench/GridLoad.h>
#include <atmoglobe/bench/SceneBench.h>
#include <atmoglobe/bench/VolumeBench.h>

#include <iostream>
#include <memory>

namespace atmoglobe::tools {

Command addBenchCommand(CLI::App& root) {
  auto o = std::make_shared<bench::VolumeBenchOptions>();
  CLI::App* c = root.add_subcommand(
      "bench", "Measure the volume marcher's speed/accuracy trade on radars or grids (and the VTK peer)");
  c->add_option("--data", o->dataDir, "Directory holding radar_nexrad/ and radar_odim/ (default ../shared/data)");
  c->add_option("--out", o->outDir, "Output directory (default out/bench)");
  c->add_flag("--quick", o->quick, "One view, a small grid, 160x90 (a smoke test)");
  c->add_option("--frames", o->frames, "Timed frames per cell (median)")->check(CLI::Range(1, 1000));
  c->add_option("--reference-step", o->referenceStepMeters, "Reference renderer step (m)")
      ->check(CLI::Range(10.0, 1000.0));
  c->add_option("--threads", o->threads, "Threads for the reference and the resampling (0: all)")
      ->check(CLI::Range(0, 256));
  c->add_flag("!--no-peer", o->peer, "Skip the VTK peer");
  c->add_flag("--reference-only", o->referenceOnly, "Only render the reference images into the cache (no GL)");
  c->add_option("--peer-script", o->peerScript, "Path of tools/bench/vtk_peer.py");
  c->add_option("--view", o->viewNames,
                "Only this view (repeatable): KLBB-oblique, KLBB-down, AU40-oblique, AU40-down");
  c->add_option("--steps", o->stepsMeters, "Only these DVR step sizes (m), e.g. --steps 250 1000")
      ->check(CLI::Range(10.0, 20000.0));
  c->add_flag(
      "--grids", o->grids,
      "The forecast-grid bench on the built-in SYNTHETIC grids (regional 400x400x35, global 0.25 deg 1440x721x37)");
  c->add_option("--grid", o->gridFile,
                "The forecast-grid bench on this grid file (CF or WRF netCDF, GRIB 1 or 2; its first ensemble member)");
  c->add_option("--var", o->gridVariable, "With --grid: the variable (default: the reader's choice)");
  c->add_option("--time", o->gridTimeIndex, "With --grid: the time step index (default 0)");
  c->add_option("--member", o->gridMember, "With --grid: the ensemble member (default: the first; listed by info)");
  c->add_option("--load-runs", o->loadRuns, "Grids: timed runs per load case (median)")->check(CLI::Range(1, 100));
  c->add_flag("!--no-load", o->load, "Grids: skip the load cases");
  c->add_flag("!--no-big", o->big, "Skip the 1280x720 frames");
  auto size = std::make_shared<std::string>();
  c->add_option("--size", *size,
                "Image size WxH of every cell and of the peer (default 320x180; quick 160x90; --scenes 480x270), e.g. "
                "1280x720");
  c->add_option("--peer-voxels", o->gridPeerMaxVoxels, "Grids: the peer's Cartesian grid cap (voxels)")
      ->check(CLI::Range(1e5, 1e9));
  addQuietOption(*c);
  auto scenes = std::make_shared<bool>(false);
  c->add_flag("--scenes", *scenes,
              "The scene-load bench: load time, peak memory and frame time of scenes of 1/4/16 SYNTHETIC radars, 1/10 "
              "time steps, globe and regional views (docs/scene-load.md); --load-runs children per scene");
  auto sceneProbe = std::make_shared<std::vector<std::string>>();
  c->add_option("--scene-probe", *sceneProbe, "(internal) run one scene case: JOB.json RESULT.json")
      ->expected(2)
      ->group("");
  auto probe = std::make_shared<std::vector<std::string>>();
  c->add_option("--load-probe", *probe, "(internal) run one load case: JOB.json RESULT.json")->expected(2)->group("");
  return {c, [o, probe, scenes, sceneProbe, size] {
            if (!probe->empty()) return bench::runLoadProbe((*probe)[0], (*probe)[1]);
            if (!sceneProbe->empty()) return bench::runSceneProbe((*sceneProbe)[0], (*sceneProbe)[1]);
            if (!size->empty()) {
              if (Status st = parseSize(*size, &o->widthPx, &o->heightPx); !st) return fail("bench", st.error());
              // The engine's frame needs a few pixels; the peer and the reference take any size.
              if (o->widthPx < 16 || o->heightPx < 16)
                return fail("bench", "--size " + *size + ": each side at least 16 pixels");
            }
            if (*scenes) {
              bench::SceneBenchOptions so;
              if (o->widthPx > 0) so.widthPx = o->widthPx, so.heightPx = o->heightPx;
              so.dataDir = o->dataDir;
              so.outDir = o->outDir;
              so.runs = o->loadRuns;
              auto r = bench::runSceneBench(so, std::cout);
              if (!r) return fail("bench", r.error());
              return 0;
            }
            Result<bench::VolumeBenchOutcome> r = bench::runVolumeBench(*o, std::cout);
            if (!r) return fail("bench", r.error());
            for (const std::string& file : r->files) std::cout << file << "\n";
            if (!r->peerNote.empty()) std::cout << r->peerNote << "\n";
            return 0;
          }};
}

}  // namespace atmoglobe::tools
