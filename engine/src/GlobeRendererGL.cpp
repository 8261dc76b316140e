#include <atmoglobe/engine/GlobeRendererGL.h>

#include <atmoglobe/globe/TileMesh.h>

#include <glm/gtc/type_ptr.hpp>

#include "LoaderGL.h"
#include "VertexLayoutGL.h"

#include <algorithm>

namespace atmoglobe::engine {

struct GlobeRendererGL::MeshGL {
  GLuint vao = 0, vbo = 0, ibo = 0;
  GLsizei indexCount = 0;
  glm::dvec3 centerEcef{0.0};
  std::size_t bytes = 0;
  ~MeshGL() {
    if (vao) glDeleteVertexArrays(1, &vao);
    if (vbo) glDeleteBuffers(1, &vbo);
    if (ibo) glDeleteBuffers(1, &ibo);
  }
};

struct GlobeRendererGL::TextureGL {
  GLuint id = 0;
  std::size_t bytes = 0;
  ~TextureGL() {
    if (id) glDeleteTextures(1, &id);
  }
};

namespace {

struct Vertex {
  glm::vec3 position;
  glm::vec2 texCoord;
};

std::shared_ptr<GlobeRendererGL::MeshGL> uploadMesh(const globe::TileMesh& mesh);

}  // namespace

Result<std::unique_ptr<GlobeRendererGL>> GlobeRendererGL::create(std::shared_ptr<globe::TileImageLoader> loader,
                                                                 const GlobeRenderOptions& options) {
  auto program = ShaderProgramGL::create("globe.vert", "globe.frag");
  if (!program) return program.forwardError();
  std::unique_ptr<GlobeRendererGL> r(new GlobeRendererGL());
  r->loader_ = std::move(loader);
  r->options_ = options;
  r->program_ = std::move(*program);
  r->uMvp_ = r->program_.uniform("u_mvp");
  r->uUvTransform_ = r->program_.uniform("u_uvTransform");
  r->uHasImagery_ = r->program_.uniform("u_hasImagery");
  r->uBaseColor_ = r->program_.uniform("u_baseColor");
  r->uImagery_ = r->program_.uniform("u_imagery");
  // Split the budget: meshes are small (~40 KB each), textures 256x256 RGBA + mips ~350 KB.
  r->meshes_ = std::make_unique<globe::LruCache<globe::TileId, std::shared_ptr<MeshGL>, globe::TileIdHash>>(
      options.gpuBudgetBytes / 4);
  r->textures_ = std::make_unique<globe::LruCache<globe::TileId, std::shared_ptr<TextureGL>, globe::TileIdHash>>(
      options.gpuBudgetBytes - options.gpuBudgetBytes / 4);
  return r;
}

GlobeRendererGL::~GlobeRendererGL() = default;

namespace {

std::shared_ptr<GlobeRendererGL::MeshGL> uploadMesh(const globe::TileMesh& mesh) {
  auto gl = std::make_shared<GlobeRendererGL::MeshGL>();
  std::vector<Vertex> vertices(mesh.positionsRelativeToCenter.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    vertices[i] = {mesh.positionsRelativeToCenter[i], mesh.texCoords[i]};
  }
  gl->centerEcef = mesh.centerEcef;
  gl->indexCount = static_cast<GLsizei>(mesh.indices.size());
  glCreateVertexArrays(1, &gl->vao);
  glCreateBuffers(1, &gl->vbo);
  glCreateBuffers(1, &gl->ibo);
  glNamedBufferStorage(gl->vbo, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(), 0);
  glNamedBufferStorage(gl->ibo, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
                       mesh.indices.data(), 0);
  glVertexArrayVertexBuffer(gl->vao, 0, gl->vbo, 0, sizeof(Vertex));
  glVertexArrayElementBuffer(gl->vao, gl->ibo);
  floatAttributeGL(gl->vao, 0, 3, offsetof(Vertex, position));
  floatAttributeGL(gl->vao, 1, 2, offsetof(Vertex, texCoord));
  gl->bytes = vertices.size() * sizeof(Vertex) + mesh.indices.size() * sizeof(std::uint32_t);
  return gl;
}

std::shared_ptr<GlobeRendererGL::TextureGL> uploadTexture(const globe::ImageRGBA8& image) {
  auto gl = std::make_shared<GlobeRendererGL::TextureGL>();
  const int levels = 1 + static_cast<int>(std::floor(std::log2(std::max(image.width, image.height))));
  glCreateTextures(GL_TEXTURE_2D, 1, &gl->id);
  glTextureStorage2D(gl->id, levels, GL_RGBA8, image.width, image.height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(gl->id, 0, 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
  // The mip levels made here, not by glGenerateTextureMipmap: the same box filter, but llvmpipe
  // draws that through its blitter, whose shaders it compiles at a process's first tile (about
  // 100 ms of a headless render's start on 2 cores); the filter on the CPU takes ~0.3 ms a tile.
  globe::ImageRGBA8 level;
  const globe::ImageRGBA8* above = &image;
  for (int l = 1; l < levels; ++l) {
    level = globe::halfSize(*above);
    glTextureSubImage2D(gl->id, l, 0, 0, level.width, level.height, GL_RGBA, GL_UNSIGNED_BYTE, level.pixels.data());
    above = &level;
  }
  glTextureParameteri(gl->id, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(gl->id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(gl->id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(gl->id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl->bytes = image.byteSize() * 4 / 3;  // with mip levels
  return gl;
}

}  // namespace

const GlobeRendererGL::TextureGL* GlobeRendererGL::findTexture(const globe::TileId& imageryTile, double priority,
                                                               GlobeFrameStats& stats, bool* pending) {
  if (auto* t = textures_->find(imageryTile)) return t->get();
  std::shared_ptr<const globe::ImageRGBA8> image = loader_->request(imageryTile, priority);
  if (!image) {
    *pending = true;
    return nullptr;
  }
  auto tex = uploadTexture(*image);
  ++stats.texturesUploaded;
  const TextureGL* raw = tex.get();
  textures_->insert(imageryTile, tex, tex->bytes);
  return raw;
}

GlobeFrameStats GlobeRendererGL::draw(const Camera& camera) {
  GlobeFrameStats stats;
  globe::SelectionOptions selection;
  selection.maxScreenSpaceErrorPx = options_.maxScreenSpaceErrorPx;
  selection.meshSegments = options_.meshSegments;
  selection.imageryMaxLevel = loader_->maxLevel();
  const globe::ViewState view = camera.viewState();
  const std::vector<globe::TileId> tiles = globe::selectTiles(view, selection, &stats.selection);

  program_.use();
  glUniform1i(uImagery_, 0);
  glUniform3fv(uBaseColor_, 1, glm::value_ptr(options_.baseColor));
  bool complete = true;
  for (const globe::TileId& tile : tiles) {
    std::shared_ptr<MeshGL> mesh;
    if (auto* m = meshes_->find(tile)) {
      mesh = *m;
    } else {
      mesh = uploadMesh(
          globe::buildTileMesh(tile, options_.meshSegments, globe::skirtDepthMeters(tile, options_.meshSegments)));
      meshes_->insert(tile, mesh, mesh->bytes);
      ++stats.meshesBuilt;
    }
    // Imagery: the tile's ancestor at the finest imagery level; nearer tiles first.
    const globe::TileId wanted = globe::ancestorTile(tile, std::min(tile.level, loader_->maxLevel()));
    const double distance = glm::length(mesh->centerEcef - camera.eyeEcef());
    bool pending = false;
    const TextureGL* texture = findTexture(wanted, -distance, stats, &pending);
    globe::TileId used = wanted;
    if (!texture) {
      complete = false;
      ++stats.tilesWithFallbackImagery;
      for (globe::TileId a = wanted; a.level > 0 && !texture;) {
        a = globe::parentTile(a);
        if (auto* t = textures_->find(a)) {
          texture = t->get();
          used = a;
        }
      }
    }
    const glm::dvec4 uv = globe::uvTransformInAncestor(tile, used);
    // Double -> float narrowing: the matrix already holds (centre - eye) in eye space.
    const glm::mat4 mvp = glm::mat4(camera.modelViewProjectionRelativeTo(mesh->centerEcef));
    glUniformMatrix4fv(uMvp_, 1, GL_FALSE, glm::value_ptr(mvp));
    glUniform4fv(uUvTransform_, 1, glm::value_ptr(glm::vec4(uv)));
    glUniform1i(uHasImagery_, texture ? 1 : 0);
    if (texture) glBindTextureUnit(0, texture->id);
    glBindVertexArray(mesh->vao);
    glDrawElements(GL_TRIANGLES, mesh->indexCount, GL_UNSIGNED_INT, nullptr);
    ++stats.tilesDrawn;
  }
  glBindVertexArray(0);
  loader_->endFrame();
  stats.gpuBytes = meshes_->bytes() + textures_->bytes();
  lastFrameComplete_ = complete;
  return stats;
}

}  // namespace atmoglobe::engine
