// CPU reference renderer (ReferenceRenderer.h): double precision, exact inverse geolocation.
#include <atmoglobe/volume/ReferenceRenderer.h>

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/StepRule.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <thread>

namespace atmoglobe::volume {
namespace {

// One layer along one ray: its sample indices [iFirst, iLast] (t_i = (i + 0.5) step inside its
// interval, i >= 0).
struct LayerRange {
  std::int64_t iFirst = 0;
  std::int64_t iLast = -1;
};

struct Context {
  const std::vector<ReferenceLayer>& layers;
  const VolumeRenderSettings& shared;  // layers[0]: mode, step, early termination
  double focalPx = 0.0;                // the step rule's pixel footprint t / focalPx; 0: none
};

VolumeSample sampleLayer(const ReferenceLayer& layer, const glm::dvec3& ecef) {
  return layer.sampler->sample(ecef, layer.settings.interpolation);
}

// The scalar field for the ISO gradient: Echo value, else opacityZeroValue.
double fieldForGradient(const ReferenceLayer& layer, const glm::dvec3& ecef) {
  const VolumeSample s = sampleLayer(layer, ecef);
  return s.state == VolumeSample::State::Echo ? s.value : layer.settings.transfer.opacityZeroValue;
}

bool isoPredicate(const ReferenceLayer& layer, const glm::dvec3& ecef) {
  const VolumeSample s = sampleLayer(layer, ecef);
  return s.state == VolumeSample::State::Echo && s.value >= layer.settings.isoValue;
}

glm::dvec4 shadeIso(const ReferenceLayer& layer, double step, const glm::dvec3& eye, const glm::dvec3& dir,
                    double tHit) {
  double lo = tHit - step, hi = tHit;
  for (int k = 0; k < 8; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (isoPredicate(layer, eye + mid * dir)) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  const glm::dvec3 p = eye + (0.5 * (lo + hi)) * dir;
  const double d = 0.5 * step;
  glm::dvec3 grad(0.0);
  for (int axis = 0; axis < 3; ++axis) {
    glm::dvec3 e(0.0);
    e[axis] = d;
    grad[axis] = (fieldForGradient(layer, p + e) - fieldForGradient(layer, p - e)) / (2.0 * d);
  }
  const double len = glm::length(grad);
  const double shade = len > 0.0 ? 0.3 + 0.7 * std::abs(glm::dot(-grad / len, dir)) : 1.0;
  const glm::dvec4 c = layer.settings.transfer.classify(layer.settings.isoValue);
  return glm::dvec4(glm::dvec3(c) * shade, 1.0);
}

glm::dvec4 marchRay(const Context& ctx, const glm::dvec3& eye, const glm::dvec3& dir, bool occlude,
                    double occluderMeters = std::numeric_limits<double>::infinity()) {
  const VolumeRenderSettings& st = ctx.shared;
  const double step = st.stepMeters;
  const std::size_t n = ctx.layers.size();
  std::vector<LayerRange> ranges(n);
  std::int64_t iBegin = std::numeric_limits<std::int64_t>::max(), iEnd = -1;
  for (std::size_t k = 0; k < n; ++k) {
    const RayInterval span = ctx.layers[k].sampler->rayInterval(eye, dir);
    if (span.empty() || span.tExitMeters < 0.0) continue;
    // i with tEnter <= (i + 0.5) step <= tExit, i >= 0.
    ranges[k].iFirst = static_cast<std::int64_t>(std::max(0.0, std::ceil(span.tEnterMeters / step - 0.5)));
    ranges[k].iLast = static_cast<std::int64_t>(std::floor(span.tExitMeters / step - 0.5));
    if (ranges[k].iLast < ranges[k].iFirst) continue;
    iBegin = std::min(iBegin, ranges[k].iFirst);
    iEnd = std::max(iEnd, ranges[k].iLast);
  }
  if (iBegin > iEnd) return glm::dvec4(0.0);
  double tLimit = occluderMeters;
  if (occlude) {
    if (const std::optional<glm::dvec3> hit = globe::intersectRayEllipsoid(eye, dir))
      tLimit = std::min(tLimit, glm::dot(*hit - eye, dir));
  }

  glm::dvec4 acc(0.0);  // DVR: premultiplied rgb, alpha
  struct MipState {
    double maxValue = -std::numeric_limits<double>::infinity();
    double tOfMax = 0.0;
    bool anyEcho = false;
  };
  std::vector<MipState> mip(st.mode == VolumeRenderMode::Mip ? n : 0);
  // The step rule (StepRule.h): the level at fine index c, the smallest of the layers' whose
  // range holds it (each by its own samplesPerCell).
  const bool adaptive = std::any_of(ctx.layers.begin(), ctx.layers.end(),
                                    [](const ReferenceLayer& l) { return l.settings.samplesPerCell > 0.0; });
  auto levelAt = [&](std::int64_t c) {
    if (!adaptive) return 0;
    const double t = (static_cast<double>(c) + 0.5) * step;
    int level = kMaxStepLevel + 1;
    for (std::size_t k = 0; k < n; ++k) {
      if (c < ranges[k].iFirst || c > ranges[k].iLast) continue;
      const VolumeRenderSettings& s = ctx.layers[k].settings;
      const double crossing = s.samplesPerCell > 0.0 ? ctx.layers[k].sampler->cellCrossingMeters(eye + t * dir, dir)
                                                     : 0.0;
      level = std::min(level, stepLevel(crossing, step, s.samplesPerCell));
    }
    if (ctx.focalPx > 0.0) level = std::min(level, stepLevel(t / ctx.focalPx, step, 1.0));
    return level > kMaxStepLevel ? 0 : level;
  };
  int level = levelAt(iBegin);
  for (std::int64_t i = alignUp(iBegin, level); i <= iEnd;) {
    const double t = (static_cast<double>(i) + 0.5) * step;
    if (!(t < tLimit)) break;
    const double stepHere = std::ldexp(step, level);  // what this sample stands for
    const glm::dvec3 p = eye + t * dir;
    // DVR over the layers at this sample: opacities and extinction-weighted colour.
    int contributing = 0;
    glm::dvec4 single(0.0);
    double transmitted = 1.0, extinction = 0.0;
    glm::dvec3 weightedRgb(0.0);
    for (std::size_t k = 0; k < n; ++k) {
      if (i < ranges[k].iFirst || i > ranges[k].iLast) continue;
      const ReferenceLayer& layer = ctx.layers[k];
      const VolumeSample s = sampleLayer(layer, p);
      if (s.state != VolumeSample::State::Echo) continue;
      switch (st.mode) {
        case VolumeRenderMode::Dvr: {
          const glm::dvec4 c = layer.settings.transfer.classify(s.value);
          if (c.a <= 0.0) break;
          const double as = layer.settings.transfer.correctedOpacity(c.a, stepHere);
          ++contributing;
          single = glm::dvec4(glm::dvec3(c), as);
          transmitted *= 1.0 - as;
          const double x = layer.settings.transfer.extinctionPerMeter(c.a);
          extinction += x;
          weightedRgb += x * glm::dvec3(c);
          break;
        }
        case VolumeRenderMode::Mip:
          if (!mip[k].anyEcho || s.value > mip[k].maxValue) {
            mip[k].maxValue = s.value;
            mip[k].tOfMax = t;
          }
          mip[k].anyEcho = true;
          break;
        case VolumeRenderMode::Iso:
          if (s.value >= layer.settings.isoValue) return shadeIso(layer, stepHere, eye, dir, t);
          break;
      }
    }
    if (contributing > 0) {
      glm::dvec3 rgb = glm::dvec3(single);
      double as = single.a;
      if (contributing > 1) {
        as = 1.0 - transmitted;
        rgb = extinction > 0.0 ? weightedRgb / extinction : glm::dvec3(0.0);
      }
      const double w = (1.0 - acc.a) * as;
      acc += glm::dvec4(rgb * w, w);
      if (acc.a >= st.earlyTerminationAlpha) return acc;
    }
    const std::int64_t c = i + (std::int64_t{1} << level);
    level = levelAt(c);
    i = alignUp(c, level);
  }
  if (st.mode == VolumeRenderMode::Mip) {
    std::vector<std::size_t> order;
    for (std::size_t k = 0; k < n; ++k)
      if (mip[k].anyEcho) order.push_back(k);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return mip[a].tOfMax < mip[b].tOfMax; });
    glm::dvec4 out(0.0);
    for (std::size_t k : order) {
      const glm::dvec4 c = ctx.layers[k].settings.transfer.classify(mip[k].maxValue);
      const double w = (1.0 - out.a) * c.a;
      out += glm::dvec4(glm::dvec3(c) * w, w);
    }
    return out;
  }
  return st.mode == VolumeRenderMode::Dvr ? acc : glm::dvec4(0.0);
}

void checkLayers(const std::vector<ReferenceLayer>& layers) {
  assert(!layers.empty());
  for (const ReferenceLayer& l : layers) {
    assert(l.sampler != nullptr);
    assert(l.settings.mode == layers[0].settings.mode && l.settings.stepMeters == layers[0].settings.stepMeters &&
           l.settings.earlyTerminationAlpha == layers[0].settings.earlyTerminationAlpha);
    (void)l;
  }
  assert(layers[0].settings.stepMeters > 0.0);
  (void)layers;
}

}  // namespace

glm::dvec4 renderReferenceRay(const std::vector<ReferenceLayer>& layers, const glm::dvec3& eyeEcef,
                              const glm::dvec3& unitDirEcef, bool occludeByEllipsoid) {
  checkLayers(layers);
  const Context ctx{layers, layers[0].settings, 0.0};
  return marchRay(ctx, eyeEcef, unitDirEcef, occludeByEllipsoid);
}

VolumeImage renderReference(const std::vector<ReferenceLayer>& layers, const RenderCamera& camera,
                            bool occludeByEllipsoid, int threads) {
  return renderReference(layers, camera, {}, occludeByEllipsoid, threads);
}

VolumeImage renderReference(const std::vector<ReferenceLayer>& layers, const RenderCamera& camera,
                            const std::vector<double>& occluderRayMeters, bool occludeByEllipsoid, int threads) {
  checkLayers(layers);
  assert(camera.widthPx >= 1 && camera.heightPx >= 1);
  const std::size_t pixels = static_cast<std::size_t>(camera.widthPx) * static_cast<std::size_t>(camera.heightPx);
  assert(occluderRayMeters.empty() || occluderRayMeters.size() == pixels);
  VolumeImage img;
  img.widthPx = camera.widthPx;
  img.heightPx = camera.heightPx;
  img.rgbaPremultiplied.assign(pixels, glm::dvec4(0.0));
  const Context ctx{layers, layers[0].settings, camera.focalLengthPx};
  const int nThreads = std::clamp(threads, 1, camera.heightPx);
  auto work = [&](int first) {
    for (int y = first; y < camera.heightPx; y += nThreads)
      for (int x = 0; x < camera.widthPx; ++x) {
        const std::size_t i =
            static_cast<std::size_t>(y) * static_cast<std::size_t>(camera.widthPx) + static_cast<std::size_t>(x);
        const glm::dvec3 dir = pixelRayDirection(camera, x + 0.5, y + 0.5);
        const double occluder = occluderRayMeters.empty() ? std::numeric_limits<double>::infinity()
                                                          : occluderRayMeters[i];
        img.rgbaPremultiplied[i] = marchRay(ctx, camera.eyeEcef, dir, occludeByEllipsoid, occluder);
      }
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < nThreads; ++k) pool.emplace_back(work, k);
  work(0);
  for (std::thread& t : pool) t.join();
  return img;
}

VolumeImage renderReference(const PolarVolume& volume, const VolumeRenderSettings& settings, const RenderCamera& camera,
                            bool occludeByEllipsoid, int threads, bool rejectOutsideShell) {
  assert(!volume.sweeps.empty());
  const PolarSampler sampler(volume, rejectOutsideShell);
  return renderReference({ReferenceLayer{&sampler, settings}}, camera, occludeByEllipsoid, threads);
}

glm::dvec4 renderReferenceRay(const PolarVolume& volume, const VolumeRenderSettings& settings,
                              const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef, bool occludeByEllipsoid) {
  assert(!volume.sweeps.empty());
  const PolarSampler sampler(volume);
  return renderReferenceRay({ReferenceLayer{&sampler, settings}}, eyeEcef, unitDirEcef, occludeByEllipsoid);
}

}  // namespace atmoglobe::volume
