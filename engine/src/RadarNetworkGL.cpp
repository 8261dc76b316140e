#include <atmoglobe/engine/RadarNetworkGL.h>

#include <atmoglobe/globe/ParallelFor.h>
#include "LoaderGL.h"

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Geolocation.h>

#include <glm/gtc/packing.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace atmoglobe::engine {

namespace {

constexpr int kRadarVec4s = 7;  // sample_network.glsl: VOL_RADAR_VEC4S
constexpr int kSweepVec4s = 2;  // VOL_sweep, VOL_sweepRays
// Networks whose coverage cells list at most this many radars march them in a loop of constant
// length (VOL_LISTED_UNROLLED). On llvmpipe a lone radar's cluster gains 1.45x; the Belgian pair
// (2 listed) gained nothing, so pairs keep the loop of varying length (docs/networks.md).
constexpr int kUnrolledListed = 1;

// The elevation -> last sweep at or below lookup of one radar over [range.x, range.y] (as
// RadarVolumeGL's; bins start where the shader computes them, in float).
std::vector<float> elevationLookup(const volume::PolarVolume& v, glm::vec2 range, int width) {
  using C = MarchConstants;
  std::vector<float> el(static_cast<std::size_t>(width), -1.0f);
  const int n = static_cast<int>(v.sweeps.size());
  int last = -1;
  for (int b = 0; b < C::kElevationBins; ++b) {
    const float start = range.x + (range.y - range.x) * static_cast<float>(b) / static_cast<float>(C::kElevationBins);
    while (last + 1 < n && static_cast<float>(v.sweeps[last + 1].elevationDeg) <= start) ++last;
    el[static_cast<std::size_t>(b)] = static_cast<float>(last);
  }
  return el;
}

}  // namespace

std::uint64_t NetworkRadarParts::bytes() const {
  std::uint64_t b = sizeof(*this) + runs.capacity() * sizeof(volume::OccupancyBox);
  for (const auto& t : rayTables) b += t.capacity() * sizeof(float);
  return b;
}

std::shared_ptr<const NetworkRadarParts> RadarNetworkGL::prepareRadar(const volume::PolarVolume& v,
                                                                      double exaggeration) {
  using C = MarchConstants;
  auto parts = std::make_shared<NetworkRadarParts>();
  parts->exaggeration = exaggeration;
  for (const auto& s : v.sweeps) parts->rayTables.push_back(volume::rayCoordinateTable(s, C::kRayTableBins));
  // Empty space: the radar's own grid's cells, a run of cells along x with values one box of
  // their largest value (create() places them in the network's frame).
  const volume::OccupancyGrid og = volume::buildOccupancyGrid(v, exaggeration);
  parts->occupancyOriginEcef = og.originEcef;
  parts->occupancyToEcef = og.localToEcef;
  for (int z = 0; z < og.cells.z; ++z)
    for (int y = 0; y < og.cells.y; ++y)
      for (int x = 0; x < og.cells.x;) {
        float m = og.maxValues[og.cellIndex(x, y, z)];
        if (m <= volume::kOccupancyEmptyValue) {
          ++x;
          continue;
        }
        const int x0 = x;
        while (x + 1 < og.cells.x && og.maxValues[og.cellIndex(x + 1, y, z)] > volume::kOccupancyEmptyValue)
          m = std::max(m, og.maxValues[og.cellIndex(++x, y, z)]);
        ++x;
        parts->runs.push_back({og.minLocal + glm::dvec3(x0, y, z) * og.cellSizeMeters,
                               og.minLocal + glm::dvec3(x, y + 1, z + 1) * og.cellSizeMeters, m});
      }
  // The highest echo: the highest corner of the occupied cells, a top corner (the frame's up is the
  // vertical at its origin, the radar). A corner (x, y, z) of the frame is about z + (x^2 + y^2) / 2R
  // above the origin's height (R = 6,371 km; the Earth's radii of curvature, 6,335-6,400 km, move
  // that by under 50 m at 300 km): the corners within 1 km of the highest by that are converted
  // exactly (globe::ecefToGeodetic), the others cannot be the highest.
  constexpr double kTwoR = 2.0 * 6371000.0;
  auto approxHeight = [&](const glm::dvec3& c) { return c.z + (c.x * c.x + c.y * c.y) / kTwoR; };
  auto corners = [](const volume::OccupancyBox& run, auto&& f) {
    for (int c = 0; c < 4; ++c) f(glm::dvec3((c & 1) ? run.hi.x : run.lo.x, (c & 2) ? run.hi.y : run.lo.y, run.hi.z));
  };
  double highest = -1e300;
  for (const volume::OccupancyBox& run : parts->runs)
    corners(run, [&](const glm::dvec3& c) { highest = std::max(highest, approxHeight(c)); });
  for (const volume::OccupancyBox& run : parts->runs)
    corners(run, [&](const glm::dvec3& c) {
      if (approxHeight(c) < highest - 1000.0) return;
      parts->echoTopMeters =
          std::max(parts->echoTopMeters, globe::ecefToGeodetic(og.originEcef + og.localToEcef * c).heightMeters);
    });
  return parts;
}

Result<std::unique_ptr<RadarNetworkGL>> RadarNetworkGL::create(
    std::vector<std::shared_ptr<const volume::PolarVolume>> radars, volume::OverlapRule rule, volume::FieldKind kind,
    double exaggeration, std::vector<std::shared_ptr<const NetworkRadarParts>> parts, RadarNetworkGL* previous,
    PreviousTexture use) {
  using C = MarchConstants;
  if (Status s = volume::validateVerticalExaggeration(exaggeration, "radar network"); !s) return s.forwardError();
  std::vector<const volume::PolarVolume*> raw;
  int maxGates = 1, maxRays = 1, sweeps = 0;
  for (const auto& r : radars) {
    const int n = static_cast<int>(r->sweeps.size());
    if (n < 1 || n > C::kMaxSweeps)
      return makeError(r->sourcePath + ": " + std::to_string(n) + " sweeps; the renderer takes 1.." +
                       std::to_string(C::kMaxSweeps));
    raw.push_back(r.get());
    maxGates = std::max(maxGates, r->maxGates);
    maxRays = std::max(maxRays, r->maxRays);
    sweeps += n;
  }
  auto sampler = volume::makeRadarNetworkSampler(raw, rule, kind);
  if (!sampler) return sampler.forwardError();

  GLint maxSize = 0, maxLayers = 0, maxBuffer = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBuffer);
  const int tileW = maxGates + 2, tileH = maxRays + 1;
  if (tileW > maxSize || tileH > maxSize || C::kRayTableBins + 1 > maxSize)
    return makeError("radar network: sweeps of " + std::to_string(maxGates) + " gates x " + std::to_string(maxRays) +
                     " rays exceed the GPU's texture size " + std::to_string(maxSize));
  const int radarCount = static_cast<int>(radars.size());
  if (sweeps + radarCount > maxSize)
    return makeError("radar network: " + std::to_string(sweeps) + " sweeps of " + std::to_string(radarCount) +
                     " radars exceed the GPU's texture size " + std::to_string(maxSize) + " (azimuth tables)");
  const int tilesPerLayer = std::max(1, std::min(maxSize / tileW, sweeps));
  const int layers = (sweeps + tilesPerLayer - 1) / tilesPerLayer;
  if (layers > maxLayers)
    return makeError("radar network: " + std::to_string(sweeps) + " sweeps need " + std::to_string(layers) +
                     " texture layers, over the GPU's " + std::to_string(maxLayers));

  // The values texture of `previous` is taken over when its layout is this one's (the same radars'
  // sweep counts, tile size and tiles per layer): only the tiles of radars whose volume is not
  // previous's (another shared_ptr) are uploaded again.
  bool reuse = previous && previous->values_ != 0 && previous->radars_.size() == radars.size() &&
               previous->tileWidth_ == tileW && previous->tileHeight_ == tileH &&
               previous->tilesPerLayer_ == tilesPerLayer && previous->layers_ == layers &&
               previous->exaggeration_ == exaggeration;
  for (std::size_t r = 0; reuse && r < radars.size(); ++r)
    reuse = previous->radars_[r]->sweeps.size() == radars[r]->sweeps.size();
  // A network that later steps kept whole is held by several steps: taking its textures over
  // would leave the others drawing nothing, so it is copied instead.
  if (previous && previous->keptByLaterSteps_) use = PreviousTexture::Copy;
  // A copy pays for the whole texture: made only where some radar's tiles are unchanged.
  const bool copy = use == PreviousTexture::Copy;
  if (reuse && copy) {
    bool anyUnchanged = false;
    for (std::size_t r = 0; r < radars.size() && !anyUnchanged; ++r) anyUnchanged = previous->radars_[r] == radars[r];
    reuse = anyUnchanged;
  }

  std::unique_ptr<RadarNetworkGL> gl(new RadarNetworkGL());
  gl->radars_ = std::move(radars);
  gl->sampler_ = std::move(*sampler);
  gl->kind_ = kind;
  gl->exaggeration_ = exaggeration;
  if (exaggeration != 1.0) gl->exaggerated_ = std::make_unique<volume::ExaggeratedSampler>(*gl->sampler_, exaggeration);
  const volume::CoverageIndex& index = gl->sampler_->coverage();
  for (const auto& r : gl->radars_) gl->origin_ += volume::localSphereBeam(r->site, r->beam).antennaEcef;
  gl->origin_ /= static_cast<double>(radarCount);
  const glm::dvec3 origin = gl->origin_;

  // Values: RGBA16F (value if echo else 0, 1 if echo, 1 if measured, 0) per texel; each sweep a
  // tile of (gates + 2) x (rays + 1): column 0 repeats gate 0 and column gates + 1 the last gate
  // (the clamp of the rule, and no filtering across tiles), row rays repeats ray 0 (the wrap).
  const int width = tilesPerLayer * tileW;
  std::vector<std::uint64_t> texels(reuse ? 0u : static_cast<std::size_t>(width) * tileH * layers, 0u);
  // Reusing: the tiles of each radar packed anew, in a buffer of its own (empty: unchanged).
  std::vector<std::vector<std::uint64_t>> tilesOf(reuse ? static_cast<std::size_t>(radarCount) : 0u);
  const std::uint64_t noEcho = glm::packHalf4x16(glm::vec4(0.0f, 0.0f, 1.0f, 0.0f));
  // The buffer: per radar 7 vec4 (site - origin, h0; the rows of ecefToEnu with M, N, Re; clip
  // radius, half beam width, sweeps, first sweep; the elevation lookup's range and row; the step
  // rule's cell scale: gate m, angle across the beam rad), per sweep
  // 2 (elevation, first gate, spacing, gates; rays), then the index's cell starts and members,
  // each a float (exact: below 2^24, checked).
  std::vector<glm::vec4> data(static_cast<std::size_t>(radarCount) * kRadarVec4s +
                              static_cast<std::size_t>(sweeps) * kSweepVec4s);
  // The azimuth and elevation tables: a row of kRayTableBins + 1 per sweep, then one per radar.
  // Reusing, the rows of the radars that changed only, in a buffer per radar (its sweeps' rows,
  // then its elevation row); the others' rows are in the table taken over or copied.
  constexpr std::size_t kRow = static_cast<std::size_t>(C::kRayTableBins) + 1;
  std::vector<float> table(reuse ? 0u : kRow * static_cast<std::size_t>(sweeps + radarCount));
  std::vector<std::vector<float>> tableOf(reuse ? static_cast<std::size_t>(radarCount) : 0u);
  gl->sweepBase_ = radarCount * kRadarVec4s;
  if (!parts.empty() && parts.size() != gl->radars_.size())
    return makeError("radar network: parts of " + std::to_string(parts.size()) + " radars for " +
                     std::to_string(radarCount));
  parts.resize(gl->radars_.size());
  // Each radar's parts (made here where missing or made at another exaggeration).
  globe::parallelFor(parts.size(), [&](std::size_t r) {
    const volume::PolarVolume& v = *gl->radars_[r];
    const auto& p = parts[r];
    if (!p || p->exaggeration != exaggeration || p->rayTables.size() != v.sweeps.size())
      parts[r] = prepareRadar(v, exaggeration);
  });
  // The occupancy grid's frame: east, north, up at the origin's direction.
  const glm::dvec3 up = glm::normalize(origin);
  glm::dvec3 east = glm::cross(glm::dvec3(0.0, 0.0, 1.0), up);
  east = glm::length(east) > 1e-6 ? glm::normalize(east) : glm::dvec3(0.0, 1.0, 0.0);
  const glm::dmat3 frame(east, glm::cross(up, east), up);
  const glm::dmat3 toFrame = glm::transpose(frame);
  std::vector<int> firstSweep(static_cast<std::size_t>(radarCount) + 1, 0);
  for (int r = 0; r < radarCount; ++r)
    firstSweep[static_cast<std::size_t>(r) + 1] =
        firstSweep[static_cast<std::size_t>(r)] +
        static_cast<int>(gl->radars_[static_cast<std::size_t>(r)]->sweeps.size());
  std::vector<double> tops(static_cast<std::size_t>(radarCount), 0.0);
  // Empty space: each radar's runs of occupied cells as boxes in the network's frame, and their
  // union. Where the previous step's empty-space grid may serve (its layout is this one's, below),
  // the boxes of radars that did not change are placed only where a changed radar's cells need
  // them, their union being the previous step's.
  const bool gridCandidate = reuse && previous->occupancy_.texture() != 0 && previous->origin_ == origin &&
                             previous->radarBoxBounds_.size() == gl->radars_.size();
  std::vector<std::vector<volume::OccupancyBox>> boxesOf(static_cast<std::size_t>(radarCount));
  std::vector<char> placed(static_cast<std::size_t>(radarCount), 0);  // not bool: written by several threads
  gl->radarBoxBounds_.assign(static_cast<std::size_t>(radarCount), volume::occupancyBounds({}));
  auto placeBoxes = [&](std::size_t r) {
    const NetworkRadarParts& p = *parts[r];
    std::vector<volume::OccupancyBox>& boxes = boxesOf[r];
    boxes.resize(p.runs.size());
    for (std::size_t i = 0; i < p.runs.size(); ++i) {
      const volume::OccupancyBox& run = p.runs[i];
      volume::OccupancyBox box{glm::dvec3(1e300), glm::dvec3(-1e300), run.maxValue};
      for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner((c & 1) ? run.hi.x : run.lo.x, (c & 2) ? run.hi.y : run.lo.y,
                                (c & 4) ? run.hi.z : run.lo.z);
        const glm::dvec3 local = toFrame * (p.occupancyOriginEcef + p.occupancyToEcef * corner - origin);
        box.lo = glm::min(box.lo, local);
        box.hi = glm::max(box.hi, local);
      }
      boxes[i] = box;
    }
    gl->radarBoxBounds_[r] = volume::occupancyBounds(boxes);
    placed[r] = 1;
  };
  // Radar r's records, tables, tiles and boxes: each radar writes its own parts of the arrays, so
  // radars are packed on several threads.
  auto pack = [&](int r) {
    const volume::PolarVolume& v = *gl->radars_[static_cast<std::size_t>(r)];
    const bool unchanged = reuse &&
                           previous->radars_[static_cast<std::size_t>(r)] == gl->radars_[static_cast<std::size_t>(r)];
    const NetworkRadarParts* p = parts[static_cast<std::size_t>(r)].get();
    // Where this radar's table rows go: the network's table, or its own buffer when reusing.
    float* ownRows = nullptr;
    if (reuse && !unchanged) {
      std::vector<float>& own = tableOf[static_cast<std::size_t>(r)];
      own.resize(kRow * (v.sweeps.size() + 1));
      ownRows = own.data();
    }
    auto tableRow = [&](int row, int k) -> float* {  // k: the radar's sweep, or -1 its elevation row
      if (!reuse) return table.data() + static_cast<std::size_t>(row) * kRow;
      if (unchanged) return nullptr;
      return ownRows + (k < 0 ? v.sweeps.size() : static_cast<std::size_t>(k)) * kRow;
    };
    const volume::LocalSphereBeam beam = volume::localSphereBeam(v.site, v.beam);
    const int n = static_cast<int>(v.sweeps.size());
    const double clip = v.clipRadiusMeters > 0.0 ? v.clipRadiusMeters : v.maxRangeMeters;
    const double hb = 0.5 * v.beamWidthDeg;
    const glm::vec2 elRange(static_cast<float>(v.sweeps.front().elevationDeg - hb),
                            static_cast<float>(v.sweeps.back().elevationDeg + hb));
    int g = firstSweep[static_cast<std::size_t>(r)];
    glm::vec4* rec = data.data() + static_cast<std::size_t>(r) * kRadarVec4s;
    rec[0] = glm::vec4(glm::vec3(beam.antennaEcef - origin), static_cast<float>(beam.antennaHeightMeters));
    const double radii[3] = {beam.meridionalRadiusMeters, beam.primeVerticalRadiusMeters, beam.effectiveRadiusMeters};
    for (int row = 0; row < 3; ++row)  // row `row` of ecefToEnu: column `row` of enuToEcef
      rec[1 + row] = glm::vec4(glm::vec3(beam.enuToEcef[row]), static_cast<float>(radii[row]));
    rec[4] = glm::vec4(static_cast<float>(clip), static_cast<float>(hb), static_cast<float>(n), static_cast<float>(g));
    rec[5] = glm::vec4(elRange.x, elRange.y, static_cast<float>(sweeps + r), 0.0f);
    const volume::PolarCellScale cells = volume::polarCellScale(v);  // the step rule's (StepRule.h)
    rec[6] = glm::vec4(static_cast<float>(cells.gateMeters), static_cast<float>(cells.acrossRad), 0.0f, 0.0f);
    if (float* row = tableRow(sweeps + r, -1)) {
      const std::vector<float> lookup = elevationLookup(v, elRange, C::kRayTableBins + 1);
      std::copy(lookup.begin(), lookup.end(), row);
    }
    // The highest point a beam reaches: the top sweep's upper edge at the clip range.
    double top = 0.0, ground = 0.0;
    volume::beamHeightAndGroundDistance(clip, v.sweeps.back().elevationDeg + hb, beam.antennaHeightMeters,
                                        beam.effectiveRadiusMeters, &top, &ground);
    // |x| of a point with data: at most the antenna's distance from the centre plus the height
    // it rises above the antenna (drawn: heights times the exaggeration), plus what the
    // ellipsoid's radius grows within the clip range (under 2 km at 500 km): a 5 km margin.
    tops[static_cast<std::size_t>(r)] =
        glm::length(beam.antennaEcef) + std::max(0.0, exaggeration * top - beam.antennaHeightMeters) + 5000.0;
    for (int k = 0; k < n; ++k, ++g) {
      const auto& s = v.sweeps[static_cast<std::size_t>(k)];
      glm::vec4* sw = data.data() + gl->sweepBase_ + static_cast<std::size_t>(g) * kSweepVec4s;
      sw[0] = glm::vec4(static_cast<float>(s.elevationDeg), static_cast<float>(s.firstGateRangeMeters),
                        static_cast<float>(s.gateSpacingMeters), static_cast<float>(s.gateCount));
      sw[1] = glm::vec4(static_cast<float>(s.rayCount), 0.0f, 0.0f, 0.0f);
      if (float* row = tableRow(g, k)) {
        const std::vector<float>& rays = p->rayTables[static_cast<std::size_t>(k)];
        std::copy(rays.begin(), rays.end(), row);
      }
      const int layer = g / tilesPerLayer;
      std::uint64_t* base = nullptr;
      std::size_t pitch = static_cast<std::size_t>(width);
      int x0 = (g % tilesPerLayer) * tileW;
      if (!reuse) {
        base = texels.data() + static_cast<std::size_t>(layer) * width * tileH;
      } else if (unchanged) {
        continue;  // its tiles are in the texture taken over
      } else {
        std::vector<std::uint64_t>& own = tilesOf[static_cast<std::size_t>(r)];
        if (own.empty()) own.assign(static_cast<std::size_t>(n) * tileW * tileH, 0u);
        base = own.data() + static_cast<std::size_t>(k) * tileW * tileH;
        pitch = static_cast<std::size_t>(tileW);
        x0 = 0;
      }
      for (int row = 0; row <= s.rayCount; ++row) {
        const int ray = row % s.rayCount;
        for (int col = 0; col < s.gateCount + 2; ++col) {
          const float value = v.value(k, ray, std::clamp(col - 1, 0, s.gateCount - 1));
          std::uint64_t t = 0;
          if (volume::isMeasuredValue(value)) t = glm::packHalf4x16(glm::vec4(value, 1.0f, 1.0f, 0.0f));
          else if (volume::isNoEcho(value)) t = noEcho;
          base[static_cast<std::size_t>(row) * pitch + x0 + col] = t;
        }
      }
    }
    if (gridCandidate && unchanged) {
      gl->radarBoxBounds_[static_cast<std::size_t>(r)] = previous->radarBoxBounds_[static_cast<std::size_t>(r)];
    } else {
      placeBoxes(static_cast<std::size_t>(r));
    }
  };
  globe::parallelFor(static_cast<std::size_t>(radarCount), [&](std::size_t r) { pack(static_cast<int>(r)); });
  const double topRadius = *std::max_element(tops.begin(), tops.end());
  std::vector<float> floats(data.size() * 4);
  std::memcpy(floats.data(), data.data(), data.size() * sizeof(glm::vec4));
  if (index.members.size() >= (1u << 24))
    return makeError("radar network: its coverage index lists " + std::to_string(index.members.size()) +
                     " radars in all, over the 2^24 the GPU's float indices hold");
  for (std::size_t c = 0; c + 1 < index.cellStart.size(); ++c)
    gl->maxListed_ = std::max(gl->maxListed_, static_cast<int>(index.cellStart[c + 1] - index.cellStart[c]));
  gl->cellBase_ = static_cast<int>(floats.size());
  for (std::uint32_t v : index.cellStart) floats.push_back(static_cast<float>(v));
  gl->memberBase_ = static_cast<int>(floats.size());
  for (std::uint32_t v : index.members) floats.push_back(static_cast<float>(v));
  floats.resize((floats.size() + 3) / 4 * 4, 0.0f);
  if (floats.size() * 4 > static_cast<std::size_t>(maxBuffer))
    return makeError("radar network: its records need " + megabytes(floats.size() * 4) +
                     ", over the GPU's shader storage block size " + megabytes(static_cast<std::size_t>(maxBuffer)));

  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  clearErrorsGL();
  // The records first: what can fail after the step before's textures are taken over is nothing
  // (the take-over allocates nothing), so a failure here leaves the step before drawing.
  glCreateBuffers(1, &gl->buffer_);
  glNamedBufferStorage(gl->buffer_, static_cast<GLsizeiptr>(floats.size() * 4), floats.data(), 0);
  gl->gpuBytes_ += floats.size() * 4;
  if (outOfMemoryGL()) return makeError("radar network: the GPU is out of memory for its tables");
  const std::size_t valueBytes = static_cast<std::size_t>(width) * tileH * layers * 8;
  if (reuse) {
    if (copy) {
      // Copied on the GPU: `previous` draws on (a loop that keeps its steps).
      gl->values_ = makeVolumeTextureGL(GL_TEXTURE_2D_ARRAY, GL_LINEAR);
      glTextureStorage3D(gl->values_, 1, GL_RGBA16F, width, tileH, layers);
      if (outOfMemoryGL())
        return makeError("radar network: the GPU is out of memory for its " + megabytes(valueBytes) + " texture of " +
                         std::to_string(sweeps) + " sweeps");
      glCopyImageSubData(previous->values_, GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0, gl->values_, GL_TEXTURE_2D_ARRAY, 0, 0, 0,
                         0, width, tileH, layers);
      // A copy that failed would leave the unchanged radars' tiles undefined: an error, not a picture.
      if (const GLenum e = glGetError(); e != GL_NO_ERROR)
        return makeError("radar network: copying the step before's " + megabytes(valueBytes) +
                         " texture on the GPU failed (GL error " + std::to_string(e) + ")");
    } else {
      // Taken over: `previous` no longer draws (its values are 0) and must be dropped.
      gl->values_ = previous->values_;
      previous->values_ = 0;
      previous->gpuBytes_ -= std::min(previous->gpuBytes_, valueBytes);
    }
    for (int r = 0; r < radarCount; ++r) {
      const std::vector<std::uint64_t>& own = tilesOf[static_cast<std::size_t>(r)];
      if (own.empty()) continue;
      ++gl->radarsUploaded_;
      for (int g = firstSweep[static_cast<std::size_t>(r)], k = 0; g < firstSweep[static_cast<std::size_t>(r) + 1];
           ++g, ++k)
        glTextureSubImage3D(gl->values_, 0, (g % tilesPerLayer) * tileW, 0, g / tilesPerLayer, tileW, tileH, 1, GL_RGBA,
                            GL_HALF_FLOAT, own.data() + static_cast<std::size_t>(k) * tileW * tileH);
    }
  } else {
    gl->values_ = makeVolumeTextureGL(GL_TEXTURE_2D_ARRAY, GL_LINEAR);
    glTextureStorage3D(gl->values_, 1, GL_RGBA16F, width, tileH, layers);
    if (outOfMemoryGL())
      return makeError("radar network: the GPU is out of memory for its " + megabytes(valueBytes) + " texture of " +
                       std::to_string(sweeps) + " sweeps");
    glTextureSubImage3D(gl->values_, 0, 0, 0, 0, width, tileH, layers, GL_RGBA, GL_HALF_FLOAT, texels.data());
    gl->radarsUploaded_ = radarCount;
  }
  gl->gpuBytes_ += valueBytes;
  gl->tileHeight_ = tileH;
  gl->layers_ = layers;
  gl->valuesSize_ = glm::vec2(static_cast<float>(width), static_cast<float>(tileH));
  gl->tileWidth_ = tileW;
  gl->tilesPerLayer_ = tilesPerLayer;
  gl->rayTableRows_ = sweeps + radarCount;
  const std::size_t tableBytes = kRow * static_cast<std::size_t>(gl->rayTableRows_) * 4;
  if (reuse && !copy) {
    gl->rayTable_ = previous->rayTable_;
    previous->rayTable_ = 0;
    previous->gpuBytes_ -= std::min(previous->gpuBytes_, tableBytes);
  } else {
    gl->rayTable_ = makeVolumeTextureGL(GL_TEXTURE_2D, GL_LINEAR);
    glTextureStorage2D(gl->rayTable_, 1, GL_R32F, C::kRayTableBins + 1, gl->rayTableRows_);
    if (outOfMemoryGL())
      return makeError("radar network: the GPU is out of memory for its " + megabytes(tableBytes) + " azimuth tables");
    if (reuse) {
      glCopyImageSubData(previous->rayTable_, GL_TEXTURE_2D, 0, 0, 0, 0, gl->rayTable_, GL_TEXTURE_2D, 0, 0, 0, 0,
                         C::kRayTableBins + 1, gl->rayTableRows_, 1);
      if (const GLenum e = glGetError(); e != GL_NO_ERROR)
        return makeError("radar network: copying the step before's " + megabytes(tableBytes) +
                         " azimuth tables on the GPU failed (GL error " + std::to_string(e) + ")");
    } else {
      glTextureSubImage2D(gl->rayTable_, 0, 0, 0, C::kRayTableBins + 1, gl->rayTableRows_, GL_RED, GL_FLOAT,
                          table.data());
    }
  }
  // The rows of the radars that changed: their sweeps' (consecutive), then their elevation row.
  for (int r = 0; r < static_cast<int>(tableOf.size()); ++r) {
    const std::vector<float>& own = tableOf[static_cast<std::size_t>(r)];
    if (own.empty()) continue;
    const int first = firstSweep[static_cast<std::size_t>(r)];
    const int n = firstSweep[static_cast<std::size_t>(r) + 1] - first;
    glTextureSubImage2D(gl->rayTable_, 0, 0, first, C::kRayTableBins + 1, n, GL_RED, GL_FLOAT, own.data());
    glTextureSubImage2D(gl->rayTable_, 0, 0, sweeps + r, C::kRayTableBins + 1, 1, GL_RED, GL_FLOAT,
                        own.data() + static_cast<std::size_t>(n) * kRow);
  }
  gl->gpuBytes_ += tableBytes;

  const volume::BoundingSphere enclosing = gl->referenceSampler().boundingSphere();
  gl->enclosing_ = glm::vec4(glm::vec3(enclosing.centreEcef - origin), static_cast<float>(enclosing.radiusMeters));
  gl->top_ = glm::vec4(glm::vec3(-origin), static_cast<float>(topRadius));
  gl->topRadiusMeters_ = topRadius;
  gl->echoTopMeters_ = -std::numeric_limits<double>::infinity();
  for (const auto& p : parts) gl->echoTopMeters_ = std::max(gl->echoTopMeters_, p->echoTopMeters);
  // Empty-space cells of about 2 km across and 500 m up, at most 2^23 (32 MiB of floats): the
  // frame is tangent at the origin, so a continental cluster's box is hundreds of km deep with
  // the Earth's curvature, and 32 fixed layers were 15 km each; a lone radar's are about what
  // 256 x 256 x 32 gave it (docs/networks.md).
  volume::OccupancyBox bounds = volume::occupancyBounds({});
  for (const volume::OccupancyBox& b : gl->radarBoxBounds_) bounds = volume::occupancyBounds(bounds, b);
  const glm::ivec3 cells = volume::occupancyCellsOver(bounds, glm::dvec3(2000.0, 2000.0, 500.0), std::size_t{1} << 23);
  auto sourcesWhere = [&](auto&& reaches) {
    std::vector<std::span<const volume::OccupancyBox>> sources;
    for (std::size_t r = 0; r < boxesOf.size(); ++r)
      if (reaches(r)) sources.emplace_back(boxesOf[r]);
    return sources;
  };
  // The previous step's grid serves where its layout is this one's (the union of the boxes did
  // not move): only the cells of the changed radars' old and new boxes are computed again, from
  // the boxes of every radar that reaches them, and uploaded (volume::rebuildOccupancyCells;
  // equal to the grid built whole, OccupancyGridTest).
  if (gridCandidate && !volume::empty(bounds) && !previous->occupancy_.grid().maxValues.empty() &&
      volume::sameOccupancyLayout(volume::occupancyLayout(origin, frame, bounds, cells), previous->occupancy_.grid())) {
    const volume::OccupancyGrid& before = previous->occupancy_.grid();
    auto cellsOf = [&](const volume::OccupancyBox& b) {
      return volume::empty(b) ? volume::OccupancyCellRange{} : volume::occupancyCellsOf(before, b.lo, b.hi);
    };
    std::vector<volume::OccupancyCellRange> ranges;
    for (std::size_t r = 0; r < gl->radars_.size(); ++r) {
      if (previous->radars_[r] == gl->radars_[r]) continue;
      const volume::OccupancyCellRange a = cellsOf(previous->radarBoxBounds_[r]), b = cellsOf(gl->radarBoxBounds_[r]);
      if (a.empty() && b.empty()) continue;
      ranges.push_back(a.empty()   ? b
                       : b.empty() ? a
                                   : volume::OccupancyCellRange{glm::min(a.first, b.first), glm::max(a.last, b.last)});
    }
    auto reachesAny = [&](std::size_t r) {
      const volume::OccupancyCellRange c = cellsOf(gl->radarBoxBounds_[r]);
      return std::any_of(ranges.begin(), ranges.end(),
                         [&](const volume::OccupancyCellRange& range) { return volume::overlaps(c, range); });
    };
    std::vector<std::size_t> toPlace;
    for (std::size_t r = 0; r < boxesOf.size(); ++r)
      if (!placed[r] && reachesAny(r)) toPlace.push_back(r);
    globe::parallelFor(toPlace.size(), [&](std::size_t k) { placeBoxes(toPlace[k]); });
    std::vector<std::vector<std::span<const volume::OccupancyBox>>> sources;
    for (const volume::OccupancyCellRange& range : ranges)
      sources.push_back(
          sourcesWhere([&](std::size_t r) { return volume::overlaps(cellsOf(gl->radarBoxBounds_[r]), range); }));
    if (copy) {
      auto copied = previous->occupancy_.copyGL();
      if (!copied) return makeError("radar network: " + copied.error());
      gl->occupancy_ = std::move(*copied);
    } else {
      gl->occupancy_ = std::move(previous->occupancy_);
    }
    gl->occupancy_.rebuildCells(ranges, sources);
    for (const volume::OccupancyCellRange& range : ranges)
      gl->occupancyCellsBuilt_ += static_cast<std::size_t>(range.last.x - range.first.x + 1) *
                                  static_cast<std::size_t>(range.last.y - range.first.y + 1) *
                                  static_cast<std::size_t>(range.last.z - range.first.z + 1);
    return gl;
  }
  std::vector<std::size_t> toPlace;
  for (std::size_t r = 0; r < boxesOf.size(); ++r)
    if (!placed[r]) toPlace.push_back(r);
  globe::parallelFor(toPlace.size(), [&](std::size_t k) { placeBoxes(toPlace[k]); });
  gl->occupancy_ = OccupancyGridGL(
      volume::buildOccupancyGrid(origin, frame, sourcesWhere([](std::size_t) { return true; }), bounds, cells));
  gl->occupancyCellsBuilt_ = gl->occupancy_.grid().maxValues.size();
  return gl;
}

Result<std::vector<std::shared_ptr<RadarNetworkGL>>> RadarNetworkGL::createByCluster(
    const std::vector<std::shared_ptr<const volume::PolarVolume>>& radars, volume::OverlapRule rule,
    volume::FieldKind kind, double exaggeration, const std::vector<std::shared_ptr<const NetworkRadarParts>>& parts,
    const std::vector<std::shared_ptr<RadarNetworkGL>>& previous, PreviousTexture use) {
  if (!parts.empty() && parts.size() != radars.size())
    return makeError("radar network: parts of " + std::to_string(parts.size()) + " radars for " +
                     std::to_string(radars.size()));
  std::vector<volume::BoundingSphere> spheres;
  for (const auto& r : radars) spheres.push_back(volume::PolarSampler(*r).boundingSphere());
  std::vector<volume::VolumeCluster> clusters = volume::clusterBySphere(spheres);
  std::stable_sort(clusters.begin(), clusters.end(),
                   [](const volume::VolumeCluster& a, const volume::VolumeCluster& b) {
                     return a.members.size() > b.members.size();
                   });
  std::vector<std::shared_ptr<RadarNetworkGL>> out;
  std::vector<bool> taken(previous.size(), false);
  auto sameSites = [](const RadarNetworkGL& p, const std::vector<std::shared_ptr<const volume::PolarVolume>>& m) {
    if (p.radars_.size() != m.size()) return false;
    for (std::size_t j = 0; j < m.size(); ++j) {
      const volume::GeolocationSite &a = p.radars_[j]->site, &b = m[j]->site;
      if (a.latDeg != b.latDeg || a.lonDeg != b.lonDeg ||
          a.antennaHeightEllipsoidMeters != b.antennaHeightEllipsoidMeters)
        return false;
    }
    return true;
  };
  for (const volume::VolumeCluster& c : clusters) {
    std::vector<std::shared_ptr<const volume::PolarVolume>> members;
    std::vector<std::shared_ptr<const NetworkRadarParts>> memberParts;
    for (std::size_t i : c.members) {
      members.push_back(radars[i]);
      if (!parts.empty()) memberParts.push_back(parts[i]);
    }
    // A cluster of the same sites in the previous step: kept whole where none of its volumes
    // changed, else its values texture is taken over or copied.
    std::shared_ptr<RadarNetworkGL> same;
    for (std::size_t k = 0; k < previous.size() && !same; ++k)
      if (!taken[k] && previous[k] && sameSites(*previous[k], members)) {
        taken[k] = true;
        same = previous[k];
      }
    if (same && same->drawable() && same->radars_ == members && same->sampler_->rule() == rule && same->kind_ == kind &&
        same->exaggeration_ == exaggeration) {
      same->keptByLaterSteps_ = true;
      out.push_back(std::move(same));
      continue;
    }
    auto gl = create(std::move(members), rule, kind, exaggeration, std::move(memberParts), same.get(), use);
    if (!gl) return gl.forwardError();
    out.push_back(std::move(*gl));
  }
  return out;
}

RadarNetworkGL::~RadarNetworkGL() {
  for (GLuint t : {values_, rayTable_})
    if (t) glDeleteTextures(1, &t);
  if (buffer_) glDeleteBuffers(1, &buffer_);
}

std::vector<std::string> RadarNetworkGL::samplerDefines(const VolumeRenderOptions& options) const {
  const int rule = sampler_->rule() == volume::OverlapRule::WeightedMean ? 0
                   : sampler_->rule() == volume::OverlapRule::LowestBeam ? 1
                                                                         : 2;
  return {std::string("INTERPOLATION ") + (options.render.interpolation == volume::Interpolation::Nearest ? "0" : "1"),
          "RULE " + std::to_string(rule), std::string("EXAGGERATED ") + (exaggeration_ != 1.0 ? "1" : "0"),
          "LISTED_UNROLLED " + std::to_string(maxListed_ <= kUnrolledListed ? maxListed_ : 0)};
}

std::optional<FarFieldExtent> RadarNetworkGL::farFieldExtent() const {
  // Its slabs are at true heights (FarFieldGL::kSlabBoundariesMeters): none when exaggerated.
  if (exaggeration_ != 1.0) return std::nullopt;
  const volume::CoverageIndex& index = sampler_->coverage();
  FarFieldExtent e;
  // The index's rows are in geocentric latitude, which differs from the geodetic by under 0.2 deg.
  e.southDeg = std::max(-90.0, index.latMinDeg - 0.2);
  e.northDeg = std::min(90.0, index.latMinDeg + index.rows * index.cellDeg + 0.2);
  e.westDeg = index.lonOriginDeg;
  e.eastDeg = index.lonOriginDeg + std::min(360.0, index.columns * index.cellDeg);
  // Every beam is below the sphere of topRadiusMeters_; over the box the ellipsoid is nowhere
  // nearer the centre than at its latitude farthest from the equator.
  const double farthestDeg = std::max(std::abs(e.southDeg), std::abs(e.northDeg));
  e.topMeters = topRadiusMeters_ - glm::length(globe::geodeticToEcef({farthestDeg, 0.0, 0.0}));
  // Nothing is drawn above the highest echo (NoEcho and NoData classify clear): the slabs stop
  // there (a 230 km VCP's top beam reaches tens of km, storms a third of that).
  if (!(echoTopMeters_ > 0.0)) return std::nullopt;
  e.topMeters = std::min(e.topMeters, echoTopMeters_);
  return e;
}

void RadarNetworkGL::setSamplerUniforms(const SamplerBindingGL& b) const {
  UniformCacheGL& u = *b.uniforms;
  const std::string& p = b.prefix;
  const volume::CoverageIndex& index = sampler_->coverage();
  glUniform1i(u(p + "values"), b.firstUnit);
  glUniform1i(u(p + "rayTable"), b.firstUnit + 1);
  glUniform2f(u(p + "valuesInvSize"), 1.0f / valuesSize_.x, 1.0f / valuesSize_.y);
  glUniform1f(u(p + "tileWidth"), static_cast<float>(tileWidth_));
  glUniform1i(u(p + "tilesPerLayer"), tilesPerLayer_);
  glUniform1f(u(p + "rayTableRows"), static_cast<float>(rayTableRows_));
  glUniform1i(u(p + "sweepBase"), sweepBase_);
  glUniform1i(u(p + "cellBase"), cellBase_);
  glUniform1i(u(p + "memberBase"), memberBase_);
  const glm::vec3 origin(origin_);
  glUniform3fv(u(p + "originEcef"), 1, glm::value_ptr(origin));
  glUniform4f(u(p + "coverage"), static_cast<float>(index.latMinDeg), static_cast<float>(index.lonOriginDeg),
              static_cast<float>(index.cellDeg), 0.0f);
  glUniform2i(u(p + "coverageCells"), index.columns, index.rows);
  glUniform4fv(u(p + "enclosing"), 1, glm::value_ptr(enclosing_));
  glUniform4fv(u(p + "top"), 1, glm::value_ptr(top_));
  glUniform1f(u(p + "exaggeration"), static_cast<float>(exaggeration_));
}

void RadarNetworkGL::bindSamplerTextures(const SamplerBindingGL& b, const VolumeRenderOptions& options) const {
  glBindTextureUnit(static_cast<GLuint>(b.firstUnit), values_);
  glBindSampler(static_cast<GLuint>(b.firstUnit),
                options.render.interpolation == volume::Interpolation::Nearest ? b.nearestSampler : 0);
  glBindTextureUnit(static_cast<GLuint>(b.firstUnit + 1), rayTable_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(b.slot), buffer_);
}

}  // namespace atmoglobe::engine
