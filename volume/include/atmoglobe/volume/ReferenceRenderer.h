#pragma once
// The CPU reference volume renderer: double precision, each kind's exact sampling rule through
// the VolumeSampler interface (a radar volume: antennaCoordinatesExact + samplePolar), the
// transfer function of TransferFunction.h. It is the yardstick for every error figure of the GPU
// marcher (which implements the same rules: docs/volume-rendering.md). GL-free, no engine
// dependency: the camera comes as plain data with the engine::Camera convention (RenderCamera.h).
//
// Per pixel (see renderReference for the full rule): a ray from the eye through the pixel
// centre; samples at t_i = (i + 0.5) * step (metres from the eye, so the sample grid is
// anchored at the eye, not at a volume's entry point), for each layer only inside its ray
// interval (VolumeSampler::rayInterval; a radar: the sphere of radius clipRadiusMeters around
// the antenna, PolarVolume.h) and before the ray's first hit of the WGS84 ellipsoid.
#include <atmoglobe/volume/PolarVolume.h>
#include <atmoglobe/volume/RenderCamera.h>
#include <atmoglobe/volume/TransferFunction.h>
#include <atmoglobe/volume/VolumeImage.h>
#include <atmoglobe/volume/VolumeRenderSettings.h>
#include <atmoglobe/volume/VolumeSampler.h>

#include <glm/glm.hpp>

#include <vector>

namespace atmoglobe::volume {

/// One volume of a reference render: its sampler (not owned; must outlive the call) and settings.
struct ReferenceLayer {
  const VolumeSampler* sampler = nullptr;
  VolumeRenderSettings settings;
};

/// Renders the layers together with the double-precision reference rule. Mode, step and early
/// termination are layers[0]'s (the others must agree, asserted); transfer, interpolation and
/// iso value are each layer's own. For each pixel:
///  - samples at t_i = (i + 0.5) * step along the unit ray from the eye, i >= 0, t_i before the
///    ray's first hit of the WGS84 ellipsoid if occludeByEllipsoid (globe::intersectRayEllipsoid);
///    layer k is sampled at t_i only when t_i lies in its rayInterval (so a pixel pays only for the
///    layers its ray crosses, and only along their intervals); with samplesPerCell > 0 only the
///    t_i the step rule picks (StepRule.h), each standing for its step 2^L step ("step" below is
///    that sample's);
///  - DVR: for each layer with an Echo sample, c_k = classify(value), a_k = correctedOpacity(c_k.a,
///    step). Where volumes overlap the emission-absorption integral of all of them is taken:
///    extinctions add, so the sample's opacity is a = 1 - prod(1 - a_k) and its colour the
///    extinction-weighted mean sum(x_k c_k) / sum(x_k), x_k = extinctionPerMeter(c_k.a) (with one
///    layer: a = a_k, colour c_k). Front to back, premultiplied: C += (1 - A) a rgb, A += (1 - A) a;
///    stop once A >= earlyTerminationAlpha;
///  - MIP: per layer the largest Echo value m_k along the ray and where it was first reached; the
///    layers' pixels (classify(m_k).rgb * a, a = classify(m_k).a, no step correction) are
///    composited front to back in the order of those positions; no Echo anywhere: transparent;
///  - ISO: the first sample i at which some layer has an Echo value >= its isoValue (the first
///    such layer in layer order); between lo = t_i - step (the previous sample position, not
///    clamped) and hi = t_i, 8 bisection steps on the predicate "that layer's sample is Echo with
///    value >= isoValue" (true -> hi = mid, else lo = mid); the surface point is p = eye + 0.5 (lo +
///    hi) dir. Normal n = -normalize(grad f), f = that layer's Echo value, or its opacityZeroValue
///    for NoEcho/NoData, by central differences along ECEF x, y, z with delta = step / 2 (zero
///    gradient: shade 1). Pixel = (classify(isoValue).rgb * (0.3 + 0.7 |dot(n, dir)|), 1). No
///    crossing: transparent.
/// Rows are split over `threads` std::threads (row y goes to thread y mod threads); the result
/// does not depend on the thread count. Cost: one sample per layer per t_i in its interval (a
/// radar: one antennaCoordinatesExact, ~1 us, except where provablyEmpty rejects the point).
VolumeImage renderReference(const std::vector<ReferenceLayer>& layers, const RenderCamera& camera,
                            bool occludeByEllipsoid = true, int threads = 2);

/// As above, with the scene's other occluders: occluderRayMeters[y * widthPx + x] (row 0 = top;
/// +inf where nothing) is the distance along pixel (x, y)'s ray to the first opaque surface drawn
/// before the volumes (in the engine: the frame's depth buffer, globe tiles and models), so that
/// the reference is occluded exactly as the GPU marcher is. Samples at t >= that distance are not
/// taken, as for the ellipsoid hit.
VolumeImage renderReference(const std::vector<ReferenceLayer>& layers, const RenderCamera& camera,
                            const std::vector<double>& occluderRayMeters, bool occludeByEllipsoid, int threads);

/// The colour of one ray (premultiplied RGBA) by the rule of renderReference (no camera: the step
/// rule without its pixel-footprint limit).
glm::dvec4 renderReferenceRay(const std::vector<ReferenceLayer>& layers, const glm::dvec3& eyeEcef,
                              const glm::dvec3& unitDirEcef, bool occludeByEllipsoid);

/// One radar volume: renderReference with one PolarSampler layer. `rejectOutsideShell` switches
/// the sampler's pre-rejection (PolarSampler::provablyEmpty); the image is bit-identical either
/// way (tested).
VolumeImage renderReference(const PolarVolume& volume, const VolumeRenderSettings& settings, const RenderCamera& camera,
                            bool occludeByEllipsoid = true, int threads = 2, bool rejectOutsideShell = true);
glm::dvec4 renderReferenceRay(const PolarVolume& volume, const VolumeRenderSettings& settings,
                              const glm::dvec3& eyeEcef, const glm::dvec3& unitDirEcef, bool occludeByEllipsoid);

}  // namespace atmoglobe::volume
