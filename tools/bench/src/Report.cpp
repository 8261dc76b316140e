#include <atmoglobe/bench/Report.h>

#include <atmoglobe/bench/Format.h>
#include <atmoglobe/globe/AtomicFile.h>
#include <atmoglobe/globe/Image.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <ostream>
#include <sstream>
#include <thread>

namespace atmoglobe::bench {

namespace fs = std::filesystem;

std::vector<Aggregate> aggregate(const std::vector<Row>& rows, const std::vector<Cell>& cells) {
  std::vector<Aggregate> out;
  for (const Cell& c : cells) {
    Aggregate a;
    a.cell = c;
    a.minPsnrDb = std::numeric_limits<double>::infinity();
    int n = 0;
    for (const Row& r : rows) {
      if (!sameCell(r.cell, c)) continue;
      a.meanMs += r.medianMs;
      a.meanAbs += r.error.meanAbs;
      a.maxAbs = std::max(a.maxAbs, r.error.maxAbs);
      a.meanPsnrDb += std::min(r.error.psnrDb, 99.0);
      a.minPsnrDb = std::min(a.minPsnrDb, r.error.psnrDb);
      ++n;
    }
    if (n == 0) continue;
    a.meanMs /= n, a.meanAbs /= n, a.meanPsnrDb /= n;
    out.push_back(a);
  }
  // Pareto front among DVR cells: no other cell is at least as fast and at least as accurate
  // (mean abs error) and strictly better in one.
  for (Aggregate& a : out) {
    if (a.cell.mode != volume::VolumeRenderMode::Dvr) continue;
    a.pareto = true;
    for (const Aggregate& b : out) {
      if (&a == &b || b.cell.mode != volume::VolumeRenderMode::Dvr) continue;
      if (b.meanMs <= a.meanMs && b.meanAbs <= a.meanAbs && (b.meanMs < a.meanMs || b.meanAbs < a.meanAbs)) {
        a.pareto = false;
        break;
      }
    }
  }
  return out;
}

std::string machineLine(const std::string& gl) {
  std::string cpu;
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  std::ostringstream s;
  s << "CPU: " << cpu << ", " << std::thread::hardware_concurrency() << " hardware threads; GL: " << gl;
  return s.str();
}

void writeCsv(std::ostream& csv, const std::vector<Row>& rows) {
  csv << "view,volume,mode,step_m,image_scale,interpolation,beam,classification,width_px,height_px,median_ms,mean_abs,"
         "max_abs,psnr_db,engine_default,samples_per_cell,refine_threshold\n";
  for (const Row& r : rows) {
    csv << r.view << "," << r.volume << "," << modeName(r.cell.mode) << "," << r.cell.stepMeters << ","
        << r.cell.imageScale << "," << interpName(r.cell.interpolation) << "," << beamName(r.cell) << ","
        << classificationName(r.cell) << "," << r.widthPx << "," << r.heightPx << "," << formatG(r.medianMs, 5) << ","
        << formatG(r.error.meanAbs, 5) << "," << formatG(r.error.maxAbs, 5) << "," << formatG(r.error.psnrDb, 5) << ","
        << (isEngineDefault(r.cell) ? 1 : 0) << "," << r.cell.samplesPerCell << "," << r.cell.refineThreshold << "\n";
  }
}

engine::ScatterPlot errorTimePlot(const BenchReport& report) {
  engine::ScatterPlot plot;
  plot.title = std::string(report.kind == "grid" ? "Forecast grids" : "Radar volume marcher") +
               ": error vs frame time (" + std::to_string(report.widthPx) + "x" + std::to_string(report.heightPx) +
               ", mean of " + std::to_string(report.views.size()) + " views)";
  plot.xLabel = "median frame time (ms, log)";
  plot.yLabel = "mean abs error vs reference (8-bit steps)";
  plot.logX = true;
  const glm::u8vec4 colors[6] = {{31, 119, 180, 255}, {255, 127, 14, 255},  {44, 160, 44, 255},
                                 {214, 39, 40, 255},  {148, 103, 189, 255}, {140, 86, 75, 255}};
  std::vector<const Aggregate*> front;
  for (const Aggregate& a : report.aggregates) {
    if (a.cell.mode != volume::VolumeRenderMode::Dvr) continue;
    const int ci = (a.cell.classification == engine::Classification::Preintegrated ? 4
                    : a.cell.interpolation == volume::Interpolation::Linear        ? 0
                                                                                   : 2) +
                   (a.cell.beam == engine::BeamApproximation::EffectiveEarthLocalSphere ? 0 : 1);
    engine::PlotPoint p;
    p.x = a.meanMs, p.y = a.meanAbs, p.color = colors[ci];
    p.radiusPx = a.cell.imageScale == 1.0 ? 5 : a.cell.imageScale == 0.5 ? 4 : 3;
    if (isEngineDefault(a.cell)) {
      p.ring = true;
      p.label = "default";
    }
    if (a.pareto) front.push_back(&a);
    plot.points.push_back(p);
  }
  std::sort(front.begin(), front.end(), [](const Aggregate* a, const Aggregate* b) { return a->meanMs < b->meanMs; });
  engine::PlotLine line;
  line.color = {120, 120, 120, 255};
  for (const Aggregate* a : front) line.points.push_back({a->meanMs, a->meanAbs});
  plot.lines.push_back(line);
  plot.legend = {{"linear, 4/3 Earth", colors[0]},
                 {"linear, straight", colors[1]},
                 {"nearest, 4/3 Earth", colors[2]},
                 {"nearest, straight", colors[3]},
                 {"linear, 4/3 Earth, pre-integrated", colors[4]},
                 {"linear, straight, pre-integrated", colors[5]},
                 {"grey line: Pareto front", {120, 120, 120, 255}},
                 {"disc size: image scale 1/.5/.25", {0, 0, 0, 255}}};
  return plot;
}

void writeMarkdown(std::ostream& md, const BenchReport& r) {
  const int w = r.widthPx, h = r.heightPx;
  md << "# atmoglobe bench: radar volume marcher\n\n";
  md << "Machine: " << r.machine << "\n\n";
  md << "Image " << w << "x" << h << " px, " << r.frames << " timed frames per cell (median, glFinish after each, "
     << "frames taken round-robin over the cells after one untimed round), volume only over black (no globe). Error against the CPU reference (double, exact "
     << "inverse, linear, step " << formatG(r.referenceStepMeters)
     << " m, full resolution, no empty-space skipping; only samples proven outside the shell skip the inverse, bit-identical): "
     << "mean / max absolute difference in 8-bit steps over RGB, PSNR in dB. For image scale < 1 the frame is the "
     << "small image upsampled bilinearly by the composite pass (what the user sees).\n\n";
  md << "## Volumes\n\n| volume | file | field | sweeps | GPU bytes | Cartesian grid at near-range resolution (float32) | ratio |\n|---|---|---|---|---|---|---|\n";
  for (const VolumeSummary& v : r.volumes) {
    const double gpu = static_cast<double>(v.gpuBytes);
    md << "| " << v.key << " | " << v.path << " | " << v.fieldName << " | " << v.sweeps << " | "
       << formatG(gpu / 1e6, 4) << " MB | " << formatG(v.cartesianBytes / 1e9, 4) << " GB | "
       << formatG(v.cartesianBytes / gpu, 4) << "x |\n";
  }
  md << "\n## Views\n\n| view | lat | lon | height (m) | heading | pitch | fovY |\n|---|---|---|---|---|---|---|\n";
  for (const BenchView& v : r.views) {
    md << "| " << v.name << " | " << formatG(v.pose.latDeg, 7) << " | " << formatG(v.pose.lonDeg, 7) << " | "
       << formatG(v.pose.heightMeters) << " | " << formatG(v.pose.headingDeg, 4) << " | " << formatG(v.pose.pitchDeg, 4)
       << " | " << formatG(v.fovYDeg) << " |\n";
  }
  md << "\nReferences: " << r.referencesRendered << " rendered this run (" << formatG(r.referenceSeconds, 4) << " s on "
     << r.referenceThreads << " threads), " << r.referencesCached << " read from the cache (" << r.referenceCacheDir
     << ").\n";
  if (!r.convergence.empty()) {
    md << "\nReference convergence (DVR, 80x45, step " << formatG(r.referenceStepMeters) << " m against "
       << formatG(r.referenceStepMeters / 2) << " m):\n\n| view | mean abs | max abs | PSNR dB |\n|---|---|---|---|\n";
    for (const auto& c : r.convergence)
      md << "| " << c.view << " | " << formatG(c.error.meanAbs, 3) << " | " << formatG(c.error.maxAbs, 3) << " | "
         << formatG(c.error.psnrDb, 3) << " |\n";
  }
  md << "\n## All settings, mean over views (sorted by time)\n\n"
     << "| mode | step (m) | scale | interp. | beam | classification | frame (ms) | mean abs | max abs | PSNR mean (dB) | PSNR min (dB) | Pareto | default |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<Aggregate> sorted = r.aggregates;
  std::sort(sorted.begin(), sorted.end(), [](const Aggregate& a, const Aggregate& b) { return a.meanMs < b.meanMs; });
  for (const Aggregate& a : sorted) {
    md << "| " << modeName(a.cell.mode) << " | " << stepName(a.cell) << " | " << scaleName(a.cell) << " | "
       << interpName(a.cell.interpolation) << " | " << beamName(a.cell) << " | " << classificationName(a.cell) << " | "
       << formatG(a.meanMs, 4) << " | " << formatG(a.meanAbs, 3) << " | " << formatG(a.maxAbs, 3) << " | "
       << formatG(a.meanPsnrDb, 3) << " | " << formatG(a.minPsnrDb, 3) << " | " << (a.pareto ? "yes" : "") << " | "
       << (isEngineDefault(a.cell) ? "**yes**" : "") << " |\n";
  }
  md << "\n## Per view\n\n| view | setting | frame (ms) | mean abs | max abs | PSNR (dB) |\n|---|---|---|---|---|---|\n";
  for (const Row& row : r.rows)
    md << "| " << row.view << " | " << cellLabel(row.cell) << (isEngineDefault(row.cell) ? " (default)" : "") << " | "
       << formatG(row.medianMs, 4) << " | " << formatG(row.error.meanAbs, 3) << " | " << formatG(row.error.maxAbs, 3)
       << " | " << formatG(row.error.psnrDb, 3) << " |\n";
  if (!r.big.empty()) {  // none with --no-big, or where the 1280x720 cells have errors (bigRows)
    md << "\n## Default setting at 1280x720 (time only)\n\n| view | frame (ms) |\n|---|---|\n";
    for (const auto& b : r.big) md << "| " << b.view << " | " << formatG(b.ms, 4) << " |\n";
  }
  md << "\n## Peer: Cartesian grid rendered by VTK\n\n";
  if (!r.peer.note.empty()) md << r.peer.note << "\n\n";
  for (const auto& [key, g] : r.peer.grids) {
    double gpu = 0.0;
    for (const VolumeSummary& v : r.volumes)
      if (v.key == key) gpu = static_cast<double>(v.gpuBytes);
    md << "- " << key << ": grid " << g.nx << " x " << g.ny << " x " << g.nz << " at " << formatG(g.spacingMeters, 4)
       << " m (finest gate spacing " << formatG(g.nativeSpacingMeters)
       << " m), box = ENU bounding box of the gates above "
       << "the zero-opacity value, float32: " << formatG(g.bytes() / 1e6, 5) << " MB vs our GPU "
       << formatG(gpu / 1e6, 4) << " MB (" << formatG(g.bytes() / gpu, 3) << "x). "
       << (g.coarsenedReason.empty() ? "" : "Coarsened: " + g.coarsenedReason + ". ") << "Resampled in "
       << formatG(g.resampleSeconds, 3)
       << " s with the fast inverse (local sphere + closed-form beam model), max error "
       << "vs the exact inverse over 20000 random voxels: " << formatG(g.maxRangeErrorMeters, 3) << " m range, "
       << formatG(g.maxAzimuthErrorDeg, 3) << " deg azimuth, " << formatG(g.maxElevationErrorDeg, 3)
       << " deg elevation.\n";
  }
  const std::vector<PeerResult>& peer = r.peer.results;
  if (!peer.empty()) {
    md << "\n| view | renderer | frame (ms) | mean abs | max abs | PSNR (dB) | note |\n|---|---|---|---|---|---|---|\n";
    for (const PeerResult& p : peer) {
      md << "| " << p.view << " | VTK " << p.mapper << " | " << formatG(p.medianMs, 4) << " | "
         << (p.ok ? formatG(p.error.meanAbs, 3) : "-") << " | " << (p.ok ? formatG(p.error.maxAbs, 3) : "-") << " | "
         << (p.ok ? formatG(p.error.psnrDb, 3) : "-") << " | " << p.note << " |\n";
    }
    md << "\nOurs at the default on the same views:\n\n| view | frame (ms) | mean abs | max abs | PSNR (dB) |\n|---|---|---|---|---|\n";
    for (const Row& row : r.rows)
      if (isEngineDefault(row.cell) && row.cell.mode == volume::VolumeRenderMode::Dvr)
        md << "| " << row.view << " | " << formatG(row.medianMs, 4) << " | " << formatG(row.error.meanAbs, 3) << " | "
           << formatG(row.error.maxAbs, 3) << " | " << formatG(row.error.psnrDb, 3) << " |\n";
    // The comparison that counts: our fastest DVR cell at equal or lower error, per VTK run.
    md << "\nOurs against each VTK run at equal or lower error (the fastest of our DVR cells on that view, at "
       << r.widthPx << "x" << r.heightPx << ", whose mean abs error is at most VTK's):\n\n"
       << "| view | VTK renderer | VTK (ms) | VTK mean abs | ours: setting | ours (ms) | ours mean abs | faster (VTK ms / "
          "ours ms) |\n|---|---|---|---|---|---|---|---|\n";
    for (const PeerResult& p : peer) {
      if (!p.ok) continue;
      md << "| " << p.view << " | VTK " << p.mapper << " | " << formatG(p.medianMs, 4) << " | "
         << formatG(p.error.meanAbs, 3) << " | ";
      const Row* ours = fastestAtOrBelowError(r.rows, p.view, p.error.meanAbs);
      if (!ours) {
        md << "none at that error | | | |\n";
        continue;
      }
      md << cellLabel(ours->cell) << " | " << formatG(ours->medianMs, 4) << " | " << formatG(ours->error.meanAbs, 3)
         << " | " << formatG(p.medianMs / ours->medianMs, 3) << "x |\n";
    }
    md << "\nVTK process peak resident memory: " << formatG(peer.front().peakRssMb, 4) << " MB.\n";
  }
  md << "\nTotal bench time: " << formatG(r.totalSeconds, 4) << " s.\n";
}

const Row* fastestAtOrBelowError(const std::vector<Row>& rows, const std::string& view, double meanAbs) {
  const Row* best = nullptr;
  for (const Row& r : rows)
    if (r.view == view && r.cell.mode == volume::VolumeRenderMode::Dvr && r.error.meanAbs <= meanAbs &&
        (!best || r.medianMs < best->medianMs))
      best = &r;
  return best;
}

void writeGridMarkdown(std::ostream& md, const BenchReport& r) {
  md << "# atmoglobe bench: forecast grids\n\n";
  md << "Machine: " << r.machine << "\n\n";
  md << "Volume only over black, each view occluded by the WGS84 ellipsoid (the reference stops at it, the marcher "
        "gets its exact depth). The GPU draws the crop of the grid the view can see; the reference (double, "
        "linear, step "
     << formatG(r.referenceStepMeters)
     << " m, full resolution) samples the whole grid, so a crop that cut off anything visible would show as "
        "error. Frame: median of "
     << r.frames
     << " frames (glFinish after each, round-robin over the cells). Error: mean / max absolute "
        "difference in 8-bit steps over RGB, PSNR.\n\n";
  md << "## Grids\n\n| grid | file | variable |\n|---|---|---|\n";
  for (const VolumeSummary& v : r.volumes) md << "| " << v.key << " | " << v.path << " | " << v.fieldName << " |\n";
  md << "\n## Views\n\n| view | lat | lon | height (m) | heading | pitch | fovY | GPU volume (crop) |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const BenchView& v : r.views) {
    double gpu = 0;
    for (const Row& row : r.rows)
      if (row.view == v.name) gpu = static_cast<double>(row.gpuBytes);
    md << "| " << v.name << " | " << formatG(v.pose.latDeg, 7) << " | " << formatG(v.pose.lonDeg, 7) << " | "
       << formatG(v.pose.heightMeters) << " | " << formatG(v.pose.headingDeg, 4) << " | " << formatG(v.pose.pitchDeg, 4)
       << " | " << formatG(v.fovYDeg) << " | lat " << formatG(v.crop.southDeg, 4) << ".." << formatG(v.crop.northDeg, 4)
       << ", lon " << formatG(v.crop.westDeg, 5) << ".." << formatG(v.crop.eastDeg, 5) << ": " << formatG(gpu / 1e6, 4)
       << " MB |\n";
  }
  if (!r.loads.empty()) {
    md << "\n## Load: the reader against the I/O floor\n\n"
          "Each case in a fresh child process (peak = its VmHWM); median of the timed runs, page cache warm. Floor: "
          "plain nc_get_vara of the same hyperslabs (the variable and what the heights come from) into a buffer "
          "of the stored type, no conversion; for GRIB, plain ecCodes: the same messages (the variable's and those "
          "its heights come from) read at their offsets and their values decoded. Bytes: the reader's bytesRead / "
          "the floor's elements x stored size (GRIB: message bytes).\n\n"
          "| grid | case | columns x levels | reader (ms) | floor (ms) | reader / floor | reader bytes | floor bytes | "
          "reader peak (MB) | floor peak (MB) |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const LoadCase& c : r.loads) {
      md << "| " << c.grid << " | " << c.name << " | ";
      if (c.hasReader) md << c.reader.columns << " x " << c.reader.levels;
      md << " | " << (c.hasReader ? formatG(c.reader.medianMs, 4) : "-") << " | " << formatG(c.floor.medianMs, 4)
         << " | "
         << (c.hasReader && c.floor.medianMs > 0 ? formatG(c.reader.medianMs / c.floor.medianMs, 3) + "x" : "-")
         << " | " << (c.hasReader ? formatG(static_cast<double>(c.reader.bytes) / 1e6, 4) + " MB" : "-") << " | "
         << formatG(static_cast<double>(c.floor.bytes) / 1e6, 4) << " MB | "
         << (c.hasReader ? formatG(c.reader.peakRssMb, 4) : "-") << " | " << formatG(c.floor.peakRssMb, 4) << " |";
      if (!c.reader.error.empty() || !c.floor.error.empty()) md << " " << c.reader.error << " " << c.floor.error;
      md << "\n";
    }
  }
  if (!r.convergence.empty()) {
    md << "\nReference convergence (DVR, 80x45, step " << formatG(r.referenceStepMeters) << " m against "
       << formatG(r.referenceStepMeters / 2) << " m):\n\n| view | mean abs | max abs | PSNR dB |\n|---|---|---|---|\n";
    for (const auto& c : r.convergence)
      md << "| " << c.view << " | " << formatG(c.error.meanAbs, 3) << " | " << formatG(c.error.maxAbs, 3) << " | "
         << formatG(c.error.psnrDb, 3) << " |\n";
  }
  md << "\nReferences: " << r.referencesRendered << " rendered this run (" << formatG(r.referenceSeconds, 4) << " s on "
     << r.referenceThreads << " threads), " << r.referencesCached << " from the cache.\n";
  md << "\n## All settings at " << r.widthPx << "x" << r.heightPx << ", mean over views (sorted by time)\n\n"
     << "| mode | step (m) | scale | interp. | classification | frame (ms) | mean abs | max abs | PSNR mean (dB) | "
        "PSNR min (dB) | Pareto | default |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<Aggregate> sorted = r.aggregates;
  std::sort(sorted.begin(), sorted.end(), [](const Aggregate& a, const Aggregate& b) { return a.meanMs < b.meanMs; });
  for (const Aggregate& a : sorted) {
    md << "| " << modeName(a.cell.mode) << " | " << stepName(a.cell) << " | " << scaleName(a.cell) << " | "
       << interpName(a.cell.interpolation) << " | " << classificationName(a.cell) << " | " << formatG(a.meanMs, 4)
       << " | " << formatG(a.meanAbs, 3) << " | " << formatG(a.maxAbs, 3) << " | " << formatG(a.meanPsnrDb, 3) << " | "
       << formatG(a.minPsnrDb, 3) << " | " << (a.pareto ? "yes" : "") << " | "
       << (isEngineDefault(a.cell) ? "**yes**" : "") << " |\n";
  }
  auto perView = [&](const std::vector<Row>& rows, const std::string& title) {
    md << "\n## " << title << "\n\n| view | size | setting | frame (ms) | mean abs | max abs | PSNR (dB) |\n"
       << "|---|---|---|---|---|---|---|\n";
    for (const Row& row : rows)
      md << "| " << row.view << " | " << row.widthPx << "x" << row.heightPx << " | " << cellLabel(row.cell)
         << (isEngineDefault(row.cell) ? " (default)" : "") << " | " << formatG(row.medianMs, 4) << " | "
         << formatG(row.error.meanAbs, 3) << " | " << formatG(row.error.maxAbs, 3) << " | "
         << formatG(row.error.psnrDb, 3) << " |\n";
  };
  perView(r.bigRows, "1280x720 (DVR, linear, point; error against the 1280x720 reference)");
  if (!r.detailRows.empty()) {
    md << "\n## Level of detail: the default setting on the coarser copy the engine marches there\n\n"
       << "Where a pixel spans two or more of the grid's columns the engine marches a block-mean copy "
          "(volume/GridDetail.h); each row against the same reference as the grid's own rows above.\n\n"
       << "Level 0 is the grid itself (the default setting, timed frame by frame in turn with the copy). The last columns: "
          "against the reference of 4 x 4 rays a pixel averaged, what the pixel covers.\n\n"
       << "| view | size | level | frame (ms) | mean abs | max abs | PSNR (dB) | 4x4 reference: mean abs | "
          "max abs | PSNR (dB) |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Row& row : r.detailRows) {
      md << "| " << row.view << " | " << row.widthPx << "x" << row.heightPx << " | " << row.detailLevel << " | "
         << formatG(row.medianMs, 4) << " | " << formatG(row.error.meanAbs, 3) << " | " << formatG(row.error.maxAbs, 3)
         << " | " << formatG(row.error.psnrDb, 3) << " | ";
      if (row.pixelAverageError)
        md << formatG(row.pixelAverageError->meanAbs, 3) << " | " << formatG(row.pixelAverageError->maxAbs, 3) << " | "
           << formatG(row.pixelAverageError->psnrDb, 3) << " |\n";
      else md << "- | - | - |\n";
    }
  }
  perView(r.rows, "Per view at " + std::to_string(r.widthPx) + "x" + std::to_string(r.heightPx));
  md << "\n## Peer: each view's crop resampled to a Cartesian grid, rendered by VTK\n\n";
  if (!r.peer.note.empty()) md << r.peer.note << "\n\n";
  for (const auto& [key, g] : r.peer.grids) {
    md << "- " << key << ": grid " << g.nx << " x " << g.ny << " x " << g.nz << " at " << formatG(g.spacingMeters, 4)
       << " m (finest level spacing where the data are visible " << formatG(g.nativeSpacingMeters, 4)
       << " m), float32: " << formatG(g.bytes() / 1e6, 5) << " MB. "
       << (g.coarsenedReason.empty() ? "" : "Coarsened: " + g.coarsenedReason + ". ") << "Resampled in "
       << formatG(g.resampleSeconds, 3) << " s with the grid's own exact sampler; trilinear reconstruction against "
       << "it over " << g.reconstructionPoints << " random points (values below the zero-opacity value as that "
       << "value): max " << formatG(g.maxReconstructionError, 3) << ", rms " << formatG(g.rmsReconstructionError, 3)
       << " (field units).\n";
  }
  if (!r.peer.results.empty()) {
    md << "\nOurs against each VTK run at equal or lower error: the fastest of our DVR cells on that view whose "
          "mean abs error is at most VTK's. Memory: our GPU volume (the crop: values, heights, lookup tables, "
          "empty-space grid) against VTK's Cartesian grid, and VTK's process peak. Target: faster and at least "
          "10x less memory.\n\n"
          "| view | VTK mapper | VTK frame (ms) | VTK mean abs / PSNR | VTK grid (MB) | VTK peak RSS (MB) | ours: "
          "setting | ours (ms) | ours mean abs / PSNR | our GPU volume (MB) | faster | less memory (grid) | "
          "target |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const PeerResult& p : r.peer.results) {
      const auto git = r.peer.grids.find(p.view);
      const double vtkBytes = git != r.peer.grids.end() ? git->second.bytes() : 0.0;
      md << "| " << p.view << " | " << p.mapper << " | " << formatG(p.medianMs, 4) << " | "
         << (p.ok ? formatG(p.error.meanAbs, 3) + " / " + formatG(p.error.psnrDb, 3) : "-") << " | "
         << formatG(vtkBytes / 1e6, 4) << " | " << formatG(p.peakRssMb, 4) << " | ";
      const Row* ours = p.ok ? fastestAtOrBelowError(r.rows, p.view, p.error.meanAbs) : nullptr;
      if (!ours) {
        md << "none at that error | | | | | | no |\n";
        continue;
      }
      const double speed = p.medianMs / ours->medianMs, mem = vtkBytes / static_cast<double>(ours->gpuBytes);
      md << cellLabel(ours->cell) << " | " << formatG(ours->medianMs, 4) << " | " << formatG(ours->error.meanAbs, 3)
         << " / " << formatG(ours->error.psnrDb, 3) << " | " << formatG(static_cast<double>(ours->gpuBytes) / 1e6, 4)
         << " | " << formatG(speed, 3) << "x | " << formatG(mem, 3) << "x | "
         << (speed > 1.0 && mem >= 10.0 ? "met" : "not met") << " |\n";
    }
    md << "\nVTK notes:";
    for (const PeerResult& p : r.peer.results) md << " " << p.view << " " << p.mapper << ": " << p.note << ";";
    md << "\n";
  }
  md << "\nTotal bench time: " << formatG(r.totalSeconds, 4) << " s.\n";
}

Status writeReport(const std::string& outDir, const BenchReport& report, std::vector<std::string>* written) {
  const fs::path dir(outDir);
  const std::string stem = report.kind == "grid" ? "grid_bench" : "volume_bench";
  const std::string csvPath = (dir / (stem + ".csv")).string();
  {
    std::ostringstream csv;
    std::vector<Row> rows = report.rows;
    rows.insert(rows.end(), report.bigRows.begin(), report.bigRows.end());
    writeCsv(csv, rows);
    if (auto s = globe::writeFileAtomic(csvPath, csv.str()); !s) return s.forwardError();
  }
  const std::string pngPath = (dir / (stem + ".png")).string();
  if (auto s = globe::writePng(pngPath, engine::drawScatterPlot(errorTimePlot(report), 960, 600)); !s) {
    return s.forwardError();
  }
  const std::string mdPath = (dir / (stem + ".md")).string();
  {
    std::ostringstream md;
    if (report.kind == "grid") writeGridMarkdown(md, report);
    else writeMarkdown(md, report);
    if (auto s = globe::writeFileAtomic(mdPath, md.str()); !s) return s.forwardError();
  }
  if (written) *written = {mdPath, csvPath, pngPath};
  return Ok{};
}

}  // namespace atmoglobe::bench
