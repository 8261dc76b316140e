#include <atmoglobe/bench/Measure.h>

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace atmoglobe::bench {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void uploadDepthGL(const engine::FramebufferGL& target, const std::vector<float>& depth) {
  glTextureSubImage2D(target.depthTexture(), 0, 0, 0, target.widthPx(), target.heightPx(), GL_DEPTH_COMPONENT, GL_FLOAT,
                      depth.data());
}

void clearTargetGL(const engine::FramebufferGL& target, const std::vector<float>* depth) {
  target.bind();
  glClearDepth(0.0);
  glClearColor(0, 0, 0, 1);
  glClear(depth ? GL_COLOR_BUFFER_BIT : GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

double timeLayersGL(engine::VolumeRendererGL& renderer, const engine::Camera& camera,
                    const std::vector<engine::VolumeLayerGL>& layers, const engine::FramebufferGL& target, int frames,
                    const std::vector<float>* depth) {
  std::vector<double> ms;
  for (int f = -1; f < frames; ++f) {  // frame -1: the warm-up
    if (depth) {                       // untimed
      uploadDepthGL(target, *depth);
      glFinish();
    }
    const auto t0 = std::chrono::steady_clock::now();
    clearTargetGL(target, depth);
    renderer.draw(camera, layers, target);
    glFinish();
    if (f >= 0) ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  return median(ms);
}

GpuRun timeFramesGL(engine::VolumeRendererGL& renderer, const engine::Camera& camera, engine::VolumeGL& volume,
                    const engine::VolumeRenderOptions& options, engine::BeamApproximation beam,
                    engine::FramebufferGL& target, int frames, bool warmUp, const std::vector<float>* depth) {
  if (auto* radar = dynamic_cast<engine::RadarVolumeGL*>(&volume)) radar->setBeamApproximation(beam);
  std::vector<double> ms;
  for (int f = warmUp ? -1 : 0; f < frames; ++f) {
    if (depth) {
      glTextureSubImage2D(target.depthTexture(), 0, 0, 0, target.widthPx(), target.heightPx(), GL_DEPTH_COMPONENT,
                          GL_FLOAT, depth->data());
      glFinish();
    }
    const auto t0 = Clock::now();
    target.bind();
    glClearDepth(0.0);
    glClearColor(0, 0, 0, 0);
    glClear(depth ? GL_COLOR_BUFFER_BIT : GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    renderer.draw(camera, volume, options, target);
    glFinish();
    if (f >= 0) ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  return {median(ms), target.readColor()};
}

std::vector<GpuRun> timeCellsRoundRobinGL(engine::VolumeRendererGL& renderer, const engine::Camera& camera,
                                          engine::VolumeGL& volume, const std::vector<Cell>& cells,
                                          engine::FramebufferGL& target, int frames, const std::vector<float>* depth,
                                          const volume::TransferFunction* transfer) {
  std::vector<std::vector<double>> frameMs(cells.size());
  std::vector<GpuRun> runs(cells.size());
  for (int f = -1; f < frames; ++f) {
    for (std::size_t ci = 0; ci < cells.size(); ++ci) {
      engine::VolumeRenderOptions options = optionsFor(cells[ci]);
      if (transfer) options.render.transfer = *transfer;
      GpuRun run = timeFramesGL(renderer, camera, volume, options, cells[ci].beam, target, 1, false, depth);
      if (f >= 0) frameMs[ci].push_back(run.medianMs);
      if (f + 1 == frames) runs[ci].image = std::move(run.image);
    }
  }
  for (std::size_t ci = 0; ci < cells.size(); ++ci) runs[ci].medianMs = median(frameMs[ci]);
  return runs;
}

volume::VolumeImage fromRgba8(const globe::ImageRGBA8& img) {
  volume::VolumeImage out;
  out.widthPx = img.width;
  out.heightPx = img.height;
  out.rgbaPremultiplied.resize(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height));
  for (std::size_t i = 0; i < out.rgbaPremultiplied.size(); ++i) {
    const std::uint8_t* p = &img.pixels[4 * i];
    out.rgbaPremultiplied[i] = glm::dvec4(p[0], p[1], p[2], p[3]) / 255.0;
  }
  return out;
}

globe::ImageRGBA8 toRgba8(const volume::VolumeImage& img) {
  globe::ImageRGBA8 out = globe::ImageRGBA8::filled(img.widthPx, img.heightPx, {0, 0, 0, 255});
  for (int y = 0; y < img.heightPx; ++y)
    for (int x = 0; x < img.widthPx; ++x) {
      const glm::dvec3 c = glm::clamp(glm::dvec3(img.at(x, y)), 0.0, 1.0);
      out.set(x, y, glm::u8vec4(glm::round(c * 255.0), 255));
    }
  return out;
}

}  // namespace atmoglobe::bench
