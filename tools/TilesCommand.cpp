// `atmoglobe tiles IMAGE -o DIR [--max-level N]`: builds a geographic imagery pyramid.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "Commands.h"
#include "SceneOptions.h"
#include "atmoglobe/globe/ImageryPyramid.h"
#include "atmoglobe/globe/Progress.h"

#include <optional>

namespace atmoglobe::tools {

Command addTilesCommand(CLI::App& root) {
  struct Options {
    std::string image;
    std::string outDir;
    int maxLevel = -1;
  };
  auto options = std::make_shared<Options>();
  Command c;
  c.app = root.add_subcommand(
      "tiles",
      "Build a geographic (EPSG:4326) imagery pyramid from an equirectangular world image "
      "(PNG/JPEG, width = 2 x height, covering -180..180 x 90..-90 deg): writes DIR/pyramid.json and "
      "DIR/{z}/{x}/{y}.png, 256 px tiles, level 0 = 2 x 1 tiles. The build is atomic: DIR is replaced "
      "only when the new pyramid is complete.");
  c.app->add_option("image", options->image, "Equirectangular world image (PNG or JPEG)")->required();
  c.app->add_option("-o,--output", options->outDir, "Output pyramid directory")->required();
  c.app
      ->add_option("--max-level", options->maxLevel,
                   "Deepest level to build (default: the smallest level at least as fine as the image)")
      ->check(CLI::Range(0, globe::kMaxPyramidLevel));
  addQuietOption(*c.app);
  c.run = [options] {
    globe::PyramidBuildOptions buildOptions;
    buildOptions.maxLevel = options->maxLevel;
    // Tiles written so far (the total is known once the image is read).
    std::optional<globe::Progress> progress;
    buildOptions.progress = [&progress](std::uint64_t written, std::uint64_t total) {
      if (!progress) progress.emplace("tiles", static_cast<std::size_t>(total));
      progress->update(static_cast<std::size_t>(written));
      return true;
    };
    globe::PyramidInfo info;
    const auto start = std::chrono::steady_clock::now();
    Status built = globe::buildPyramid(options->image, options->outDir, buildOptions, &info);
    if (progress) progress->finish(!built);
    if (!built) return fail("tiles", built.error());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s: levels 0..%d, %llu tiles of %d px, %.2f s\n", options->outDir.c_str(), info.maxLevel,
                static_cast<unsigned long long>(globe::pyramidTileCount(info.maxLevel)), info.tileSizePx, seconds);
    return 0;
  };
  return c;
}

}  // namespace atmoglobe::tools
