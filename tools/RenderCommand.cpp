// atmoglobe render: draws a scene headless (EGL, no window, no X server) into a PNG.
#include "Commands.h"
#include "SceneOptions.h"

#include <atmoglobe/engine/Camera.h>
#include <atmoglobe/engine/ContextGL.h>
#include <atmoglobe/engine/FramebufferGL.h>
#include <atmoglobe/engine/SceneRendererGL.h>
#include <atmoglobe/globe/Image.h>

#include <filesystem>
#include <iostream>
#include <memory>

namespace atmoglobe::tools {

namespace {
struct RenderOptions {
  SceneOptions scene;
  std::string output = "out/render.png";
  bool stats = false;
};

int runRender(const RenderOptions& o) {
  auto scene = resolveScene(o.scene);
  if (!scene) return fail("render", scene.error());
  auto context = engine::HeadlessContextGL::create();
  if (!context) return fail("render", context.error());
  auto loader = engine::openImagery(scene->imagery, {});
  if (!loader) return fail("render", loader.error());
  auto renderer = engine::SceneRendererGL::create(*loader);
  if (!renderer) return fail("render", renderer.error());
  std::vector<engine::Marker> markers = scene->markers;
  if (auto s = populateScene(**renderer, *scene, &markers); !s) return fail("render", s.error());
  auto target = engine::FramebufferGL::create(scene->widthPx, scene->heightPx);
  if (!target) return fail("render", target.error());
  const engine::Camera camera(scene->camera, scene->fovYDeg, scene->widthPx, scene->heightPx);
  engine::SceneFrameStats stats;
  auto image = (*renderer)->renderToImage(camera, markers, **target, 64, &stats);
  if (!image) return fail("render", image.error());
  const std::filesystem::path parent = std::filesystem::path(o.output).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (ec) return fail("render", parent.string() + ": cannot create directory: " + ec.message());
  if (auto s = globe::writePng(o.output, *image); !s) return fail("render", s.error());
  if (o.stats) {
    std::cerr << "renderer: " << (*context)->describe() << "\n"
              << "tiles drawn: " << stats.globe.tilesDrawn << " (max level " << stats.globe.selection.maxLevel
              << ", visited " << stats.globe.selection.visited << ", culled frustum "
              << stats.globe.selection.culledFrustum << ", horizon " << stats.globe.selection.culledHorizon << ")\n"
              << "tiles decoded: " << (*loader)->stats().tilesDecoded << "\n";
  }
  std::cout << o.output << "\n";
  return 0;
}
}  // namespace

Command addRenderCommand(CLI::App& root) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* c = root.add_subcommand("render", "Render a scene headless (EGL, no window) to a PNG file");
  addSceneOptions(*c, options->scene);
  c->add_option("-o,--output", options->output, "Output PNG file")->capture_default_str();
  c->add_flag("--stats", options->stats, "Print renderer, tile and decoding statistics to stderr");
  c->footer("Example: atmoglobe render --camera 46,8,2e6,0,-90,0 --size 1280x720 -o out/alps.png");
  return {c, [options] { return runRender(*options); }};
}

}  // namespace atmoglobe::tools
