// The polar render layout and the sampling rule (PolarVolume.h). Double precision: this is
// the definition the GPU marcher is measured against.
#include <atmoglobe/volume/PolarVolume.h>

#include <atmoglobe/globe/Angles.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/ParallelFor.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>

namespace atmoglobe::volume {
namespace {

double wrap360(double deg) {
  double a = std::fmod(deg, 360.0);
  if (a < 0.0) a += 360.0;
  return a >= 360.0 ? 0.0 : a;  // fmod(-1e-17) + 360 rounds to 360
}

// A sweep "has the field" when values were decoded for it: rays, gates and the value array.
bool sweepHasField(const Sweep& s) {
  return s.rayCount() > 0 && s.gateCount > 0 && s.values.size() == s.rayCount() * s.gateCount;
}

// round() of the rule: floor(x + 0.5) (halves go up; GLSL's round() leaves halves to the
// implementation, floor(x + 0.5) does not).
double roundHalfUp(double x) { return std::floor(x + 0.5); }

struct Accumulator {
  double echoWeight = 0.0;
  double noEchoWeight = 0.0;
  double weightedSum = 0.0;
  void add(float v, double w) {
    if (isMeasuredValue(v)) {
      echoWeight += w;
      weightedSum += w * static_cast<double>(v);
    } else if (isNoEcho(v)) {
      noEchoWeight += w;
    }  // NoData: counts for nothing
  }
};

// Adds sweep k's texels at (r, az) with total weight `sweepWeight` to `acc`.
void accumulateSweep(const PolarVolume& v, int k, double rangeMeters, double az, double sweepWeight,
                     Interpolation interpolation, Accumulator* acc) {
  const PolarSweepLayout& s = v.sweeps[static_cast<std::size_t>(k)];
  const double g = (rangeMeters - s.firstGateRangeMeters) / s.gateSpacingMeters;
  if (!(g >= -0.5 && g <= s.gateCount - 0.5)) return;  // outside the gates: all NoData
  const double a = rayCoordinate(s, az);
  const int n = s.rayCount;
  const int lastGate = s.gateCount - 1;
  assert(interpolation == Interpolation::Linear);  // Nearest: nearestGate
  (void)interpolation;
  const double a0 = std::floor(a);
  const double g0 = std::floor(g);
  const double fa = a - a0;
  const double fg = g - g0;
  const int ray0 = static_cast<int>(a0) % n;
  const int ray1 = (ray0 + 1) % n;
  const int gate0 = std::clamp(static_cast<int>(g0), 0, lastGate);
  const int gate1 = std::clamp(static_cast<int>(g0) + 1, 0, lastGate);
  acc->add(v.value(k, ray0, gate0), sweepWeight * (1.0 - fa) * (1.0 - fg));
  acc->add(v.value(k, ray0, gate1), sweepWeight * (1.0 - fa) * fg);
  acc->add(v.value(k, ray1, gate0), sweepWeight * fa * (1.0 - fg));
  acc->add(v.value(k, ray1, gate1), sweepWeight * fa * fg);
}

}  // namespace

double rayCoordinate(const PolarSweepLayout& s, double azimuthDeg) {
  const double az = wrap360(azimuthDeg);
  const std::vector<float>& a = s.azimuthDeg;
  const int n = s.rayCount;
  // First ray with azimuth > az; the ray before it is the one at or below.
  const auto it =
      std::upper_bound(a.begin(), a.end(), az, [](double x, float v) { return x < static_cast<double>(v); });
  const int above = static_cast<int>(it - a.begin());
  const double first = static_cast<double>(a.front());
  const double last = static_cast<double>(a.back());
  const double wrapSpan = first + 360.0 - last;                     // > 0: azimuths are distinct and in [0, 360)
  if (above == 0) return (n - 1) + (az + 360.0 - last) / wrapSpan;  // before the first ray
  if (above == n) return (n - 1) + (az - last) / wrapSpan;          // after the last ray
  const double lo = static_cast<double>(a[static_cast<std::size_t>(above - 1)]);
  const double hi = static_cast<double>(a[static_cast<std::size_t>(above)]);
  return (above - 1) + (az - lo) / (hi - lo);
}

std::vector<float> rayCoordinateTable(const PolarSweepLayout& s, int bins) {
  std::vector<float> table(static_cast<std::size_t>(bins) + 1);
  const double n = s.rayCount;
  [[maybe_unused]] double previous = -2.0;
  for (int j = 0; j <= bins; ++j) {
    const double az = 360.0 * j / bins;
    double a = rayCoordinate(s, az);  // in [0, n): between the last ray and ray 0 it is >= n - 1
    // Continuous and increasing over [0, 360]: before the first ray (one turn earlier) the
    // coordinate is a - n in [-1, 0); at 360 it is the value at 0 plus n.
    if (j == bins) {
      a = static_cast<double>(table.front()) + n;
    } else if (az < static_cast<double>(s.azimuthDeg.front())) {
      a -= n;
    }
    assert(a >= previous);
    previous = a;
    table[static_cast<std::size_t>(j)] = static_cast<float>(a);
  }
  return table;
}

Result<PolarVolume> buildPolarVolume(const RadarVolume& volume, const SiteResolution& site, const BeamModel& beam) {
  const std::string& file = volume.sourcePath.empty() ? std::string("(volume)") : volume.sourcePath;
  Status beamOk = validateBeamModel(beam, file.c_str());
  if (!beamOk) return beamOk.forwardError();
  if (!std::isfinite(site.site.latDeg) || !std::isfinite(site.site.lonDeg) ||
      !std::isfinite(site.site.antennaHeightEllipsoidMeters))
    return makeError(file + ": radar site has non-finite coordinates");

  // PPI sweeps, in the volume's order (sorted by fixed angle, file order for equal angles).
  std::vector<const Sweep*> ppi;
  bool anyRhi = false;
  for (const Sweep& s : volume.sweeps) {
    if (s.mode == SweepMode::Rhi) anyRhi = true;
    if (s.mode == SweepMode::Ppi) ppi.push_back(&s);
  }
  if (ppi.empty()) {
    if (anyRhi) return makeError(file + ": RHI volumes cannot be volume-rendered yet; export or `gates` them");
    return makeError(file + ": no PPI sweep to volume-render");
  }
  if (volume.loadedField.name.empty())
    return makeError(file + ": no field values loaded (read with ReadOptions::loadValues)");
  for (const Sweep* s : ppi)
    if (!std::isfinite(s->fixedAngleDeg))
      return makeError(file + ": sweep " + std::to_string(s->indexInFile) + " has a non-finite fixed angle");
  std::stable_sort(ppi.begin(), ppi.end(),
                   [](const Sweep* a, const Sweep* b) { return a->fixedAngleDeg < b->fixedAngleDeg; });

  // Split cuts: equal fixed angles (within kSameAngleDeg) keep the first sweep that has the field.
  constexpr double kSameAngleDeg = 1e-3;
  std::vector<const Sweep*> kept;
  for (const Sweep* s : ppi) {
    if (!sweepHasField(*s)) continue;
    if (!kept.empty() && s->fixedAngleDeg - kept.back()->fixedAngleDeg < kSameAngleDeg) continue;
    kept.push_back(s);
  }
  if (kept.empty()) return makeError(file + ": no PPI sweep holds values of field " + volume.loadedField.name);

  PolarVolume out;
  out.sourcePath = volume.sourcePath;
  out.fieldName = volume.loadedField.name;
  out.fieldUnits = volume.loadedField.units;
  out.site = site.site;
  out.beam = beam;
  out.beamWidthDeg = (std::isfinite(volume.beamWidthDeg) && volume.beamWidthDeg > 0.0) ? volume.beamWidthDeg : 1.0;

  // Per sweep: rays sorted by azimuth (stable), equal azimuths keep the first ray.
  std::vector<std::vector<std::uint32_t>> rayOrder(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const Sweep& s = *kept[k];
    const std::string where = file + ": sweep " + std::to_string(s.indexInFile);
    if (!std::isfinite(s.firstGateRangeMeters) || !std::isfinite(s.gateSpacingMeters) || !(s.gateSpacingMeters > 0.0))
      return makeError(where + " has a non-finite or non-positive gate geometry");
    std::vector<double> az(s.rayCount());
    for (std::size_t r = 0; r < s.rayCount(); ++r) {
      if (!std::isfinite(s.azimuthDeg[r])) return makeError(where + " has a non-finite ray azimuth");
      // Wrapped in float so that the stored (float) azimuths are exactly what was sorted.
      az[r] = static_cast<double>(static_cast<float>(wrap360(static_cast<double>(s.azimuthDeg[r]))));
      if (az[r] >= 360.0) az[r] = 0.0;
    }
    std::vector<std::uint32_t> order(s.rayCount());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return az[a] < az[b]; });
    std::vector<std::uint32_t> unique;
    PolarSweepLayout layout;
    for (std::uint32_t r : order) {
      if (!unique.empty() && az[r] == az[unique.back()]) continue;
      unique.push_back(r);
      layout.azimuthDeg.push_back(static_cast<float>(az[r]));
    }
    layout.elevationDeg = s.fixedAngleDeg;
    layout.firstGateRangeMeters = s.firstGateRangeMeters;
    layout.gateSpacingMeters = s.gateSpacingMeters;
    layout.gateCount = static_cast<int>(s.gateCount);
    layout.rayCount = static_cast<int>(unique.size());
    out.maxRays = std::max(out.maxRays, layout.rayCount);
    out.maxGates = std::max(out.maxGates, layout.gateCount);
    out.maxRangeMeters = std::max(out.maxRangeMeters, s.firstGateRangeMeters + (s.gateCount - 1) * s.gateSpacingMeters +
                                                          0.5 * s.gateSpacingMeters);
    out.sweeps.push_back(std::move(layout));
    rayOrder[k] = std::move(unique);
  }
  if (!(out.maxRangeMeters > 0.0)) return makeError(file + ": the gates end at or before the antenna");
  {
    const glm::dvec3 antenna =
        globe::geodeticToEcef(globe::Geodetic{out.site.latDeg, out.site.lonDeg, out.site.antennaHeightEllipsoidMeters});
    const double hb = 0.5 * out.beamWidthDeg;
    const double elLo = std::max(-90.0, out.sweeps.front().elevationDeg - hb);
    const double elHi = std::min(90.0, out.sweeps.back().elevationDeg + hb);
    double farthest = out.maxRangeMeters;
    const int steps = std::max(1, static_cast<int>(std::ceil((elHi - elLo) / 0.05)));
    for (int i = 0; i <= steps; ++i) {
      const double el = elLo + (elHi - elLo) * i / steps;
      for (int k = 0; k < 8; ++k) {
        const GatePosition p = geolocateGateExact(out.site, out.beam, 45.0 * k, el, out.maxRangeMeters);
        farthest = std::max(farthest, glm::length(p.ecef - antenna));
      }
    }
    out.clipRadiusMeters = farthest * 1.001;
  }

  // The padded array: bounded so that odd sweep shapes cannot ask for an unbounded allocation.
  constexpr std::size_t kMaxValues = std::size_t{1} << 28;  // 1 GiB of float
  const std::size_t total =
      out.sweeps.size() * static_cast<std::size_t>(out.maxRays) * static_cast<std::size_t>(out.maxGates);
  if (total > kMaxValues) {
    std::ostringstream msg;
    msg << file << ": the polar layout would need " << total << " values (" << out.sweeps.size() << " sweeps x "
        << out.maxRays << " rays x " << out.maxGates << " gates), more than the limit of " << kMaxValues;
    return makeError(msg.str());
  }
  out.values.assign(total, kNoData);
  float lo = std::numeric_limits<float>::infinity(), hi = -std::numeric_limits<float>::infinity();
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const Sweep& s = *kept[k];
    for (std::size_t row = 0; row < rayOrder[k].size(); ++row) {
      const float* src = s.values.data() + static_cast<std::size_t>(rayOrder[k][row]) * s.gateCount;
      float* dst = out.values.data() +
                   (k * static_cast<std::size_t>(out.maxRays) + row) * static_cast<std::size_t>(out.maxGates);
      std::copy(src, src + s.gateCount, dst);
      for (std::uint32_t g = 0; g < s.gateCount; ++g)
        if (isMeasuredValue(src[g])) {
          lo = std::min(lo, src[g]);
          hi = std::max(hi, src[g]);
        }
    }
  }
  if (lo <= hi) {
    out.minValue = lo;
    out.maxValue = hi;
  }
  return out;
}

std::optional<PolarGate> nearestGate(const PolarVolume& v, double rangeMeters, double azimuthDeg, double elevationDeg) {
  if (v.sweeps.empty() || !std::isfinite(rangeMeters) || !std::isfinite(azimuthDeg) || !std::isfinite(elevationDeg))
    return std::nullopt;
  const double hb = 0.5 * v.beamWidthDeg;
  if (elevationDeg < v.sweeps.front().elevationDeg - hb || elevationDeg > v.sweeps.back().elevationDeg + hb)
    return std::nullopt;  // below the lowest beam / cone of silence
  int k = 0;
  for (int j = 1; j < static_cast<int>(v.sweeps.size()); ++j)  // strict <: ties keep the lower sweep
    if (std::abs(elevationDeg - v.sweeps[static_cast<std::size_t>(j)].elevationDeg) <
        std::abs(elevationDeg - v.sweeps[static_cast<std::size_t>(k)].elevationDeg))
      k = j;
  const PolarSweepLayout& s = v.sweeps[static_cast<std::size_t>(k)];
  const double g = (rangeMeters - s.firstGateRangeMeters) / s.gateSpacingMeters;
  if (!(g >= -0.5 && g <= s.gateCount - 0.5)) return std::nullopt;  // outside the gates
  PolarGate out;
  out.sweep = k;
  out.ray = static_cast<int>(roundHalfUp(rayCoordinate(s, azimuthDeg))) % s.rayCount;
  out.gate = std::clamp(static_cast<int>(roundHalfUp(g)), 0, s.gateCount - 1);
  out.elevationDeg = s.elevationDeg;
  out.azimuthDeg = static_cast<double>(s.azimuthDeg[static_cast<std::size_t>(out.ray)]);
  out.rangeMeters = s.firstGateRangeMeters + out.gate * s.gateSpacingMeters;
  out.value = v.value(k, out.ray, out.gate);
  return out;
}

PolarSample samplePolar(const PolarVolume& v, double rangeMeters, double azimuthDeg, double elevationDeg,
                        Interpolation interpolation) {
  assert(!v.sweeps.empty());
  PolarSample out;
  if (!std::isfinite(rangeMeters) || !std::isfinite(azimuthDeg) || !std::isfinite(elevationDeg)) return out;
  const int n = static_cast<int>(v.sweeps.size());
  const double hb = 0.5 * v.beamWidthDeg;
  const double e0 = v.sweeps.front().elevationDeg;
  const double eTop = v.sweeps.back().elevationDeg;
  if (elevationDeg < e0 - hb || elevationDeg > eTop + hb) return out;  // below the lowest beam / cone of silence
  const double az = wrap360(azimuthDeg);

  Accumulator acc;
  if (interpolation == Interpolation::Nearest) {
    if (const auto gate = nearestGate(v, rangeMeters, az, elevationDeg)) acc.add(gate->value, 1.0);
  } else if (elevationDeg <= e0) {
    accumulateSweep(v, 0, rangeMeters, az, 1.0, interpolation, &acc);
  } else if (elevationDeg >= eTop) {
    accumulateSweep(v, n - 1, rangeMeters, az, 1.0, interpolation, &acc);
  } else {
    // k with e_k <= el < e_{k+1}
    int k = 0;
    while (k + 1 < n && v.sweeps[static_cast<std::size_t>(k + 1)].elevationDeg <= elevationDeg) ++k;
    const double ek = v.sweeps[static_cast<std::size_t>(k)].elevationDeg;
    const double ek1 = v.sweeps[static_cast<std::size_t>(k + 1)].elevationDeg;
    const double t = (elevationDeg - ek) / (ek1 - ek);
    accumulateSweep(v, k, rangeMeters, az, 1.0 - t, interpolation, &acc);
    accumulateSweep(v, k + 1, rangeMeters, az, t, interpolation, &acc);
  }
  if (acc.echoWeight >= 0.5) {
    out.state = PolarSample::State::Echo;
    out.value = acc.weightedSum / acc.echoWeight;
  } else if (acc.echoWeight + acc.noEchoWeight >= 0.5) {
    out.state = PolarSample::State::NoEcho;
  }
  return out;
}

double cartesianEquivalentBytes(const PolarVolume& v, double bytesPerVoxel) {
  if (v.sweeps.empty()) return 0.0;
  double spacing = std::numeric_limits<double>::infinity();
  for (const PolarSweepLayout& s : v.sweeps) spacing = std::min(spacing, s.gateSpacingMeters);
  const double re = effectiveEarthRadiusMeters(v.beam, v.site.latDeg);
  const double hb = 0.5 * v.beamWidthDeg;
  // Vertical extent: from the lowest to the highest beam edge over every sweep's gates,
  // relative to the antenna (heights from the beam model, Doviak & Zrnic 2.28).
  double top = 0.0, bottom = 0.0;
  for (const PolarSweepLayout& s : v.sweeps) {
    const double rMax = s.firstGateRangeMeters + (s.gateCount - 0.5) * s.gateSpacingMeters;
    for (double r : {0.0, rMax}) {
      double h = 0.0, ground = 0.0;
      beamHeightAndGroundDistance(r, std::min(90.0, s.elevationDeg + hb), 0.0, re, &h, &ground);
      top = std::max(top, h);
      beamHeightAndGroundDistance(r, std::max(-90.0, s.elevationDeg - hb), 0.0, re, &h, &ground);
      bottom = std::min(bottom, h);
    }
  }
  const double nxy = std::ceil(2.0 * v.maxRangeMeters / spacing);
  const double nz = std::max(1.0, std::ceil((top - bottom) / spacing));
  return nxy * nxy * nz * bytesPerVoxel;
}

StraightElevationBand straightElevationBand(const PolarVolume& v, bool straightBeam) {
  StraightElevationBand band;
  if (v.sweeps.empty()) return band;
  const double hb = 0.5 * v.beamWidthDeg;
  const double radius = v.beam.earthRadiusMeters.value_or(globe::geocentricRadiusMeters(v.site.latDeg));
  band.bendDegPerMeter =
      straightBeam || !(v.beam.ke > 0.0) ? 0.0 : radiansToDegrees(std::abs(1.0 - 1.0 / v.beam.ke) / (2.0 * radius));
  band.loDeg = v.sweeps.front().elevationDeg - hb - kStraightElevationBandMarginDeg;
  band.hiDeg = v.sweeps.back().elevationDeg + hb + kStraightElevationBandMarginDeg;
  return band;
}

double StraightElevationBand::loDegAt(double rangeMeters) const {
  return std::max(-90.0, loDeg - std::max(rangeMeters, 0.0) * bendDegPerMeter);
}
double StraightElevationBand::hiDegAt(double rangeMeters) const {
  return std::min(90.0, hiDeg + std::max(rangeMeters, 0.0) * bendDegPerMeter);
}

PolarSampler::PolarSampler(const PolarVolume& volume, bool rejectOutsideShell)
    : volume_(volume), antennaEcef_(globe::geodeticToEcef(globe::Geodetic{volume.site.latDeg, volume.site.lonDeg,
                                                                          volume.site.antennaHeightEllipsoidMeters})),
      upEcef_(globe::enuAxes(volume.site.latDeg, volume.site.lonDeg)[2]), band_(straightElevationBand(volume)),
      cellScale_(polarCellScale(volume)),
      reject_(rejectOutsideShell && !volume.sweeps.empty() && volume.beam.ke > 0.0) {}

double PolarSampler::cellCrossingMeters(const glm::dvec3& ecef, const glm::dvec3& unitDirEcef) const {
  return polarCellCrossingMeters(cellScale_, ecef - antennaEcef_, unitDirEcef);
}

PolarCellScale polarCellScale(const PolarVolume& v) {
  PolarCellScale c;
  if (v.sweeps.empty()) return c;
  double gate = std::numeric_limits<double>::infinity();
  double acrossDeg = v.beamWidthDeg > 0.0 ? v.beamWidthDeg : std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < v.sweeps.size(); ++k) {
    const PolarSweepLayout& s = v.sweeps[k];
    if (s.gateSpacingMeters > 0.0) gate = std::min(gate, s.gateSpacingMeters);
    if (s.rayCount > 0) acrossDeg = std::min(acrossDeg, 360.0 / s.rayCount);
    if (k > 0 && s.elevationDeg > v.sweeps[k - 1].elevationDeg)
      acrossDeg = std::min(acrossDeg, s.elevationDeg - v.sweeps[k - 1].elevationDeg);
  }
  if (!std::isfinite(gate) || !std::isfinite(acrossDeg)) return c;
  c.gateMeters = static_cast<double>(static_cast<float>(gate));
  c.acrossRad = static_cast<double>(static_cast<float>(acrossDeg * std::numbers::pi / 180.0));
  return c;
}

BoundingSphere PolarSampler::boundingSphere() const {
  return {antennaEcef_, volume_.clipRadiusMeters > 0.0 ? volume_.clipRadiusMeters : volume_.maxRangeMeters};
}

RayInterval PolarSampler::rayInterval(const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef) const {
  const BoundingSphere s = boundingSphere();
  return raySphereInterval(eyeEcef, unitDirEcef, s.centreEcef, s.radiusMeters);
}

bool PolarSampler::provablyEmpty(const glm::dvec3& ecef) const {
  if (!reject_) return false;
  constexpr double kMinRangeMeters = 1000.0;  // the chord's elevation is ill-conditioned nearer the antenna
  const glm::dvec3 d = ecef - antennaEcef_;
  const double r = glm::length(d);
  if (!(r > kMinRangeMeters)) return false;
  const double elS = radiansToDegrees(std::asin(std::clamp(glm::dot(d, upEcef_) / r, -1.0, 1.0)));
  return elS > band_.hiDegAt(r) || elS < band_.loDegAt(r);
}

VolumeSample PolarSampler::sample(const glm::dvec3& ecef, Interpolation interpolation) const {
  if (provablyEmpty(ecef)) return VolumeSample{};  // NoData
  const AntennaCoordinates ac = antennaCoordinatesExact(volume_.site, volume_.beam, ecef);
  return samplePolar(volume_, ac.rangeMeters, ac.azimuthDeg, ac.elevationDeg, interpolation);
}

ValueRange PolarSampler::valueRange() const { return {volume_.minValue, volume_.maxValue}; }

std::string PolarSampler::description() const { return volume_.fieldName + " from " + volume_.sourcePath; }

OccupancyGrid buildOccupancyGrid(const PolarVolume& v, double exaggeration) {
  const LocalSphereBeam beam = localSphereBeam(v.site, v.beam);
  const int n = static_cast<int>(v.sweeps.size());
  const double hb = 0.5 * v.beamWidthDeg;
  constexpr int kRays = 2, kGates = 4;
  // A box per block of kRays x kGates gates holding a value, from the forward map at 3 x 3 x 3
  // points of its support. A gate block's ranges and the sweep's elevations are the same for
  // every ray block, and a ray block's azimuths for every gate block: the map's factors
  // (LocalSphereBeam::along, ::across) are made once each. Sweeps on the cores, their boxes
  // kept in sweep order.
  std::vector<std::vector<OccupancyBox>> sweepBoxes(static_cast<std::size_t>(n));
  globe::parallelFor(static_cast<std::size_t>(n), [&](std::size_t sweep) {
    const int k = static_cast<int>(sweep);
    const auto& s = v.sweeps[sweep];
    std::vector<OccupancyBox>& boxes = sweepBoxes[sweep];
    const double elLo = k > 0 ? v.sweeps[k - 1].elevationDeg : s.elevationDeg - hb;
    const double elHi = k + 1 < n ? v.sweeps[k + 1].elevationDeg : s.elevationDeg + hb;
    const double els[3] = {elLo, 0.5 * (elLo + elHi), elHi};
    // A gate block's support (one gate and one ray beyond the block on each side: linear
    // interpolation): its outer range and the map's range/elevation factor at its 3 x 3 points.
    struct GateBlock {
      double outerRangeMeters = 0.0;
      std::array<LocalSphereBeam::Along, 9> along;
    };
    std::vector<GateBlock> gateBlocks(static_cast<std::size_t>((s.gateCount + kGates - 1) / kGates));
    for (std::size_t gb = 0; gb < gateBlocks.size(); ++gb) {
      const int g0 = static_cast<int>(gb) * kGates;
      const double rA = std::max(0.0, s.firstGateRangeMeters + (g0 - 1.0) * s.gateSpacingMeters);
      const double rB = s.firstGateRangeMeters + (std::min(g0 + kGates, s.gateCount) + 0.5) * s.gateSpacingMeters;
      const double ranges[3] = {rA, 0.5 * (rA + rB), rB};
      gateBlocks[gb].outerRangeMeters = rB;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) gateBlocks[gb].along[3 * i + j] = beam.along(ranges[i], els[j]);
    }
    for (int r0 = 0; r0 < s.rayCount; r0 += kRays) {
      const double azA = s.azimuthDeg[(r0 + s.rayCount - 1) % s.rayCount];
      double azB = s.azimuthDeg[std::min(r0 + kRays, s.rayCount) % s.rayCount];
      if (azB <= azA) azB += 360.0;
      const LocalSphereBeam::Across acrosses[3] = {beam.across(azA), beam.across(0.5 * (azA + azB)), beam.across(azB)};
      for (int g0 = 0; g0 < s.gateCount; g0 += kGates) {
        float m = kOccupancyEmptyValue;
        for (int ray = r0; ray < std::min(r0 + kRays, s.rayCount); ++ray)
          for (int gate = g0; gate < std::min(g0 + kGates, s.gateCount); ++gate) {
            const float x = v.value(k, ray, gate);
            if (std::isfinite(x)) m = std::max(m, x);
          }
        if (m == kOccupancyEmptyValue) continue;
        const GateBlock& block = gateBlocks[static_cast<std::size_t>(g0 / kGates)];
        const auto& along = block.along;
        OccupancyBox b{glm::dvec3(1e30), glm::dvec3(-1e30), m};
        for (int i = 0; i < 3; ++i)
          for (const LocalSphereBeam::Across& c : acrosses)
            for (int j = 0; j < 3; ++j) {
              const glm::dvec3 p = exaggeration == 1.0
                                       ? beam.enuOf(along[3 * i + j], c)
                                       : beam.exaggerateEnu(beam.enuOf(along[3 * i + j], c), exaggeration);
              b.lo = glm::min(b.lo, p);
              b.hi = glm::max(b.hi, p);
            }
        const double rB = block.outerRangeMeters;
        // Between the sampled points the support bulges out of their box by at most the
        // sagitta of an arc of radius rB over the whole azimuth span plus that over the whole
        // elevation span (each r (1 - cos(span / 2)); the points are half a span apart, so this
        // is 4x the second-order bound), plus the beam's own curvature from the antenna to rB
        // (rB^2 / (8 Re)), plus 50 m for the local-sphere model against the exact inverse
        // (kLocalSphereMaxRangeErrorMeters) and float rounding of the GPU's cell lookup (ENU
        // positions to ~0.05 m at 500 km). KLBB: 40-600 m, against cells of 3.6 km x 300 m.
        const double azSpanRad = degreesToRadians(azB - azA), elSpanRad = degreesToRadians(elHi - elLo);
        const double bulge = rB * (2.0 - std::cos(0.5 * azSpanRad) - std::cos(0.5 * elSpanRad)) +
                             rB * rB / (8.0 * beam.effectiveRadiusMeters) + 50.0;
        // Exaggerated, the arcs between the points bulge by up to the factor more (vertically).
        const double margin = bulge * std::max(1.0, exaggeration);
        b.lo -= glm::dvec3(margin);
        b.hi += glm::dvec3(margin);
        boxes.push_back(b);
      }
    }
  });
  std::size_t total = 0;
  for (const auto& sb : sweepBoxes) total += sb.size();
  std::vector<OccupancyBox> boxes;
  boxes.reserve(total);
  for (const auto& sb : sweepBoxes) boxes.insert(boxes.end(), sb.begin(), sb.end());
  // 256 x 256 x 32 cells (4 MB as half floats; KLBB: 3.6 x 3.6 km x ~600 m): the fastest of
  // 64..384 x 64..384 x 32..128 in `atmoglobe bench` (llvmpipe, docs/bench-volume.md; with the
  // second level 32 layers beat 48 and 64 by 3-6 %).
  return buildOccupancyGrid(beam.antennaEcef, beam.enuToEcef, boxes, glm::ivec3(256, 256, 32));
}

}  // namespace atmoglobe::volume
