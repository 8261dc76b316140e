#pragma once
// The settings grid: one cell = one way of drawing (mode, step, image scale, interpolation, beam
// approximation, classification); its names in the reports, and the engine options it maps to.
#include <atmoglobe/engine/RadarVolumeGL.h>
#include <atmoglobe/engine/VolumeGL.h>
#include <atmoglobe/volume/VolumeRenderSettings.h>

#include <string>
#include <vector>

namespace atmoglobe::bench {

struct Cell {
  volume::VolumeRenderMode mode = volume::VolumeRenderMode::Dvr;
  double stepMeters = 250.0;
  /// > 0: the step follows the cells (volume/StepRule.h), stepMeters the shortest; 0: fixed.
  double samplesPerCell = 0.0;
  double imageScale = 1.0;
  /// With imageScale < 1: adaptive refinement's threshold in 8-bit steps; < 0: off.
  double refineThreshold = -1.0;
  volume::Interpolation interpolation = volume::Interpolation::Linear;
  engine::BeamApproximation beam = engine::BeamApproximation::EffectiveEarthLocalSphere;
  engine::Classification classification = engine::Classification::Point;
  /// False for kinds without a beam model (forecast grids): `beam` is then not an axis of the
  /// grid and prints as "-".
  bool beamApplies = true;
};

const char* modeName(volume::VolumeRenderMode m);   ///< dvr, mip, iso
const char* interpName(volume::Interpolation i);    ///< linear, nearest
const char* beamName(engine::BeamApproximation b);  ///< 4/3-earth, straight
const char* beamName(const Cell& c);                ///< beamName(c.beam), or "-" where the kind has no beam
/// DVR: point or preintegrated; MIP and iso: "-" (classification does not apply).
const char* classificationName(const Cell& c);
/// "250", or "250, 2/cell" for a step that follows the cells (the tables' step column).
std::string stepName(const Cell& c);
/// "0.25", or "0.25, refine 4" with adaptive refinement (the tables' scale column).
std::string scaleName(const Cell& c);
/// "dvr step 250 m[, 2 samples/cell], scale 1, linear, 4/3-earth[, pre-integrated]" (the per-view table).
std::string cellLabel(const Cell& c);
bool sameCell(const Cell& a, const Cell& b);

/// The engine's defaults (VolumeRenderOptions / VolumeRenderSettings, the radar's beam model).
bool isEngineDefault(const Cell& c);

/// The options the marcher draws the cell with: the default reflectivity transfer function,
/// empty-space skipping on (it must not change the picture, RadarMarchTest).
engine::VolumeRenderOptions optionsFor(const Cell& c);

struct GridAxes {
  std::vector<double> stepsMeters;  ///< DVR steps, increasing
  std::vector<double> imageScales;
  /// Adaptive refinement thresholds (8-bit steps) of the linear cells at scales < 1.
  std::vector<double> refineThresholds;
};

/// The standard axes: steps {125, 250, 500, 750, 1000, 1500, 2000} m x scales {1, 0.5, 0.25};
/// quick: {250, 1000} x {1, 0.5}; refine thresholds {4, 32} (quick {4}). `stepsOverride` (--steps), when not empty,
/// replaces the steps (sorted, duplicates removed).
GridAxes standardAxes(bool quick, const std::vector<double>& stepsOverride);

/// DVR: every step x scale x {nearest, linear} x {4/3-Earth, straight} with point
/// classification, each linear cell again pre-integrated (pre-integration assumes the field
/// linear between samples); then MIP and iso at the default. `beamAxis` false (forecast grids:
/// no beam model): the straight-beam cells are left out and every cell has beamApplies false.
/// Each linear 4/3-Earth cell at a scale < 1 is repeated with adaptive refinement at each of
/// axes.refineThresholds (point and pre-integrated; grids also with the step rule at each
/// `samplesPerCell`, point). Each linear 4/3-Earth cell at scale 1 is repeated with the step
/// rule at `samplesPerCell` each.
std::vector<Cell> gridCells(const GridAxes& axes, bool beamAxis = true, const std::vector<double>& samplesPerCell = {});

}  // namespace atmoglobe::bench
