#include <atmoglobe/bench/Cells.h>

#include <atmoglobe/bench/Format.h>
#include <atmoglobe/engine/VolumeLayer.h>
#include <atmoglobe/volume/TransferFunction.h>

#include <algorithm>
#include <sstream>

namespace atmoglobe::bench {

const char* modeName(volume::VolumeRenderMode m) {
  return m == volume::VolumeRenderMode::Dvr ? "dvr" : m == volume::VolumeRenderMode::Mip ? "mip" : "iso";
}
const char* interpName(volume::Interpolation i) { return i == volume::Interpolation::Linear ? "linear" : "nearest"; }
const char* beamName(engine::BeamApproximation b) {
  return b == engine::BeamApproximation::EffectiveEarthLocalSphere ? "4/3-earth" : "straight";
}

const char* beamName(const Cell& c) { return c.beamApplies ? beamName(c.beam) : "-"; }

const char* classificationName(const Cell& c) {
  if (c.mode != volume::VolumeRenderMode::Dvr) return "-";
  return c.classification == engine::Classification::Preintegrated ? "preintegrated" : "point";
}

std::string stepName(const Cell& c) {
  return formatG(c.stepMeters) + (c.samplesPerCell > 0.0 ? ", " + formatG(c.samplesPerCell) + "/cell" : "");
}

std::string scaleName(const Cell& c) {
  return formatG(c.imageScale) + (c.refineThreshold >= 0.0 ? ", refine " + formatG(c.refineThreshold) : "");
}

std::string cellLabel(const Cell& c) {
  std::ostringstream s;
  s << modeName(c.mode) << " step " << formatG(c.stepMeters) << " m";
  if (c.samplesPerCell > 0.0) s << ", " << formatG(c.samplesPerCell) << " samples/cell";
  s << ", scale " << scaleName(c) << ", " << interpName(c.interpolation);
  if (c.beamApplies) s << ", " << beamName(c.beam);
  if (c.classification == engine::Classification::Preintegrated) s << ", pre-integrated";
  return s.str();
}

bool sameCell(const Cell& a, const Cell& b) {
  return a.mode == b.mode && a.stepMeters == b.stepMeters && a.samplesPerCell == b.samplesPerCell &&
         a.imageScale == b.imageScale && a.refineThreshold == b.refineThreshold && a.interpolation == b.interpolation &&
         a.beam == b.beam && a.classification == b.classification && a.beamApplies == b.beamApplies;
}

bool isEngineDefault(const Cell& c) {
  const engine::VolumeRenderOptions d;
  // Grids (no beam axis) take the step rule by default (engine::kDefaultGridSamplesPerCell).
  const double samplesPerCell = c.beamApplies ? 0.0 : engine::kDefaultGridSamplesPerCell;
  return c.stepMeters == d.render.stepMeters && c.samplesPerCell == samplesPerCell && c.imageScale == d.imageScale &&
         c.refineThreshold == d.refineThreshold && c.interpolation == d.render.interpolation &&
         c.beam == engine::BeamApproximation::EffectiveEarthLocalSphere && c.classification == d.classification;
}

engine::VolumeRenderOptions optionsFor(const Cell& c) {
  engine::VolumeRenderOptions o;
  o.render.mode = c.mode;
  o.render.stepMeters = c.stepMeters;
  o.render.samplesPerCell = c.samplesPerCell;
  o.render.interpolation = c.interpolation;
  o.render.transfer = volume::defaultReflectivityTransfer();
  o.imageScale = c.imageScale;
  o.refineThreshold = c.refineThreshold;
  o.classification = c.classification;
  o.skipEmptySpace = true;
  return o;
}

GridAxes standardAxes(bool quick, const std::vector<double>& stepsOverride) {
  GridAxes a;
  a.stepsMeters = {125.0, 250.0, 500.0, 750.0, 1000.0, 1500.0, 2000.0};
  a.imageScales = {1.0, 0.5, 0.25};
  a.refineThresholds = {4.0, 32.0};
  if (quick) a.stepsMeters = {250.0, 1000.0}, a.imageScales = {1.0, 0.5}, a.refineThresholds = {4.0};
  if (!stepsOverride.empty()) {
    a.stepsMeters = stepsOverride;
    std::sort(a.stepsMeters.begin(), a.stepsMeters.end());
    a.stepsMeters.erase(std::unique(a.stepsMeters.begin(), a.stepsMeters.end()), a.stepsMeters.end());
  }
  return a;
}

std::vector<Cell> gridCells(const GridAxes& axes, bool beamAxis, const std::vector<double>& samplesPerCell) {
  std::vector<Cell> cells;
  for (double step : axes.stepsMeters)
    for (double scale : axes.imageScales)
      for (auto interp : {volume::Interpolation::Nearest, volume::Interpolation::Linear})
        for (auto beam :
             {engine::BeamApproximation::EffectiveEarthLocalSphere, engine::BeamApproximation::StraightLine}) {
          if (!beamAxis && beam != engine::BeamApproximation::EffectiveEarthLocalSphere) continue;
          Cell c;
          c.stepMeters = step, c.imageScale = scale, c.interpolation = interp, c.beam = beam;
          c.beamApplies = beamAxis;
          cells.push_back(c);
          // Pre-integration assumes the field linear between samples: with linear interpolation only.
          if (interp == volume::Interpolation::Linear) {
            c.classification = engine::Classification::Preintegrated;
            cells.push_back(c);
          }
          // Adaptive refinement of the small image (linear, 4/3-Earth, point and pre-integrated).
          if (interp == volume::Interpolation::Linear && scale < 1.0 &&
              beam == engine::BeamApproximation::EffectiveEarthLocalSphere)
            for (double threshold : axes.refineThresholds)
              for (auto cl : {engine::Classification::Point, engine::Classification::Preintegrated}) {
                Cell a = c;
                a.refineThreshold = threshold;
                a.classification = cl;
                cells.push_back(a);
                // Grids: with the step rule too (their default), point classification.
                if (!beamAxis && cl == engine::Classification::Point)
                  for (double n : samplesPerCell) {
                    Cell r = a;
                    r.samplesPerCell = n;
                    cells.push_back(r);
                  }
              }
          if (interp == volume::Interpolation::Linear && scale == 1.0 &&
              beam == engine::BeamApproximation::EffectiveEarthLocalSphere)
            for (double n : samplesPerCell)
              for (auto cl : {engine::Classification::Point, engine::Classification::Preintegrated}) {
                Cell a = c;
                a.samplesPerCell = n;
                a.classification = cl;
                cells.push_back(a);
              }
        }
  for (auto mode : {volume::VolumeRenderMode::Mip, volume::VolumeRenderMode::Iso}) {
    Cell c;
    c.mode = mode;
    c.beamApplies = beamAxis;
    cells.push_back(c);
  }
  return cells;
}

}  // namespace atmoglobe::bench
