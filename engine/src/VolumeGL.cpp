#include <atmoglobe/engine/VolumeGL.h>

#include <atmoglobe/engine/ShaderConstants.h>
#include <atmoglobe/globe/ParallelFor.h>
#include <atmoglobe/volume/StepRule.h>

#include "LoaderGL.h"

#include <atomic>

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

namespace atmoglobe::engine {

std::vector<std::string> marchShaderDefines() {
  using C = MarchConstants;
  std::vector<std::string> defines = {"TRANSFER_ENTRIES " + std::to_string(C::kTransferEntries),
                                      "MAX_VOLUMES " + std::to_string(C::kMaxVolumes),
                                      "STATE_NOT_ECHO " + std::to_string(C::kStateNotEcho),
                                      "STATE_ECHO " + std::to_string(C::kStateEcho),
                                      "GRID_BLOCK " + std::to_string(C::kGridBlock),
                                      "MAX_SWEEPS " + std::to_string(C::kMaxSweeps),
                                      "RAY_TABLE_BINS " + std::to_string(C::kRayTableBins),
                                      "ELEVATION_BINS " + std::to_string(C::kElevationBins),
                                      "GPU_NO_DATA " + glslFloatLiteral(C::kNoData),
                                      "GPU_NO_DATA_BELOW " + glslFloatLiteral(C::kNoDataBelow),
                                      "MAX_STEP_LEVEL " + std::to_string(volume::kMaxStepLevel),
                                      "CELL_SCALE_ENTRIES " + std::to_string(volume::CellScale::kEntries)};
  for (std::string& d : ellipsoidShaderDefines()) defines.push_back(std::move(d));
  return defines;
}

VolumeGL::VolumeGL() {
  static std::atomic<std::uint64_t> next{1};
  id_ = next.fetch_add(1);
}

GLint UniformCacheGL::operator()(const std::string& name) {
  auto it = locations_.find(name);
  if (it == locations_.end()) it = locations_.emplace(name, glGetUniformLocation(program_, name.c_str())).first;
  return it->second;
}

GLuint makeVolumeTextureGL(GLenum target) { return makeVolumeTextureGL(target, GL_NEAREST); }

GLuint makeVolumeTextureGL(GLenum target, GLint filter) {
  GLuint t = 0;
  glCreateTextures(target, 1, &t);
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, filter);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, filter);
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  return t;
}

namespace {
// The smallest half float >= x (the grid must not round a cell's maximum down below a
// threshold that a sample in it exceeds). Finite x within the half range.
std::uint16_t halfRoundedUp(float x) {
  std::uint16_t h = static_cast<std::uint16_t>(glm::packHalf1x16(x));
  if (glm::unpackHalf1x16(h) < x) {
    // Next half towards +inf: magnitude up for positives, down for negatives (-0 -> +min).
    if (h & 0x8000u) {
      h = (h == 0x8000u) ? std::uint16_t{1} : static_cast<std::uint16_t>(h - 1);
    } else {
      h = static_cast<std::uint16_t>(h + 1);
    }
  }
  return h;
}

// Uploads the cells of `r` and the blocks over them (the blocks' layers above the cells' in the
// texture) as half floats rounded up, the layers converted on several threads.
void uploadOccupancyGL(GLuint texture, const volume::OccupancyGrid& g, const volume::OccupancyCellRange& r) {
  constexpr int kB = volume::OccupancyGrid::kBlock;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  auto upload = [&](const std::vector<float>& values, glm::ivec3 dims, glm::ivec3 first, glm::ivec3 last, int zOffset) {
    const glm::ivec3 n = last - first + 1;
    std::vector<std::uint16_t> texels(static_cast<std::size_t>(n.x) * n.y * n.z);
    globe::parallelFor(static_cast<std::size_t>(n.z), [&](std::size_t zs) {
      const int z = static_cast<int>(zs);
      for (int y = 0; y < n.y; ++y)
        for (int x = 0; x < n.x; ++x)
          texels[(static_cast<std::size_t>(z) * n.y + y) * n.x + x] = halfRoundedUp(
              values[(static_cast<std::size_t>(first.z + z) * dims.y + first.y + y) * dims.x + first.x + x]);
    });
    glTextureSubImage3D(texture, 0, first.x, first.y, zOffset + first.z, n.x, n.y, n.z, GL_RED, GL_HALF_FLOAT,
                        texels.data());
  };
  upload(g.maxValues, g.cells, r.first, r.last, 0);
  upload(g.blockMaxValues, g.blocks, r.first / kB, r.last / kB, g.cells.z);
}
}  // namespace

OccupancyGridGL::OccupancyGridGL(volume::OccupancyGrid occupancy) : grid_(std::move(occupancy)) {
  const volume::OccupancyGrid& g = grid_;
  const glm::ivec3 size(g.cells.x, g.cells.y, g.cells.z + g.blocks.z);
  texture_ = makeVolumeTextureGL(GL_TEXTURE_3D);
  glTextureStorage3D(texture_, 1, GL_R16F, size.x, size.y, size.z);
  // Empty where no block is (the block layers are as wide as the cells').
  const std::uint16_t empty = halfRoundedUp(volume::kOccupancyEmptyValue);
  glClearTexSubImage(texture_, 0, 0, 0, g.cells.z, size.x, size.y, g.blocks.z, GL_RED, GL_HALF_FLOAT, &empty);
  uploadOccupancyGL(texture_, g, {glm::ivec3(0), g.cells - 1});
  gpuBytes_ = static_cast<std::size_t>(size.x) * size.y * size.z * 2;
}

Result<OccupancyGridGL> OccupancyGridGL::copyGL() const {
  OccupancyGridGL copy;
  copy.grid_ = grid_;
  const glm::ivec3 size(grid_.cells.x, grid_.cells.y, grid_.cells.z + grid_.blocks.z);
  copy.texture_ = makeVolumeTextureGL(GL_TEXTURE_3D);
  clearErrorsGL();
  glTextureStorage3D(copy.texture_, 1, GL_R16F, size.x, size.y, size.z);
  if (outOfMemoryGL())
    return makeError("the GPU is out of memory for a copy of an empty-space grid of " + std::to_string(size.x) + " x " +
                     std::to_string(size.y) + " x " + std::to_string(size.z) + " cells");
  glCopyImageSubData(texture_, GL_TEXTURE_3D, 0, 0, 0, 0, copy.texture_, GL_TEXTURE_3D, 0, 0, 0, 0, size.x, size.y,
                     size.z);
  if (const GLenum e = glGetError(); e != GL_NO_ERROR)
    return makeError("copying an empty-space grid of " + std::to_string(size.x) + " x " + std::to_string(size.y) +
                     " x " + std::to_string(size.z) + " cells on the GPU failed (GL error " + std::to_string(e) + ")");
  copy.gpuBytes_ = gpuBytes_;
  return copy;
}

void OccupancyGridGL::rebuildCells(const std::vector<volume::OccupancyCellRange>& ranges,
                                   const std::vector<std::vector<std::span<const volume::OccupancyBox>>>& sources) {
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    const volume::OccupancyCellRange r{glm::max(ranges[k].first, glm::ivec3(0)),
                                       glm::min(ranges[k].last, grid_.cells - 1)};
    if (r.empty()) continue;
    volume::rebuildOccupancyCells(grid_, r, sources[k]);
    uploadOccupancyGL(texture_, grid_, r);
  }
}

OccupancyGridGL::~OccupancyGridGL() {
  if (texture_) glDeleteTextures(1, &texture_);
}
OccupancyGridGL::OccupancyGridGL(OccupancyGridGL&& other) noexcept
    : grid_(std::move(other.grid_)), texture_(std::exchange(other.texture_, 0)),
      gpuBytes_(std::exchange(other.gpuBytes_, 0)) {}
OccupancyGridGL& OccupancyGridGL::operator=(OccupancyGridGL&& other) noexcept {
  if (this != &other) {
    if (texture_) glDeleteTextures(1, &texture_);
    grid_ = std::move(other.grid_);
    texture_ = std::exchange(other.texture_, 0);
    gpuBytes_ = std::exchange(other.gpuBytes_, 0);
  }
  return *this;
}

std::size_t textureByteLimit() {
  const char* text = std::getenv("ATMOGLOBE_MAX_TEXTURE_BYTES");
  if (!text || !*text) return 0;
  char* end = nullptr;
  const unsigned long long bytes = std::strtoull(text, &end, 10);
  return end && *end == '\0' ? static_cast<std::size_t>(bytes) : 0;
}

void clearErrorsGL() {
  for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
  }
}

bool outOfMemoryGL() {
  bool oom = false;
  for (int i = 0; i < 16; ++i) {
    const GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    oom = oom || e == GL_OUT_OF_MEMORY;
  }
  return oom;
}

std::string megabytes(std::size_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MB", static_cast<double>(bytes) / 1.0e6);
  return text;
}

}  // namespace atmoglobe::engine
