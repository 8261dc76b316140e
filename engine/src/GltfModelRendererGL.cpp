#include <atmoglobe/engine/GltfModelRendererGL.h>

#include <tiny_gltf.h>

#include <glm/gtc/type_ptr.hpp>

#include "LoaderGL.h"
#include "VertexLayoutGL.h"

#include <cstring>

namespace atmoglobe::engine {

namespace {

glm::dmat4 nodeLocalMatrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    glm::dmat4 m;
    std::memcpy(glm::value_ptr(m), node.matrix.data(), sizeof(double) * 16);  // column-major, as glTF
    return m;
  }
  glm::dmat4 m(1.0);
  if (node.translation.size() == 3)
    m[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
  // The cone export writes matrices only; rotation/scale of other files are not supported.
  return m;
}

/// Bytes of an accessor as a typed pointer, after checking bounds; nullptr if it does not fit.
template <class T>
const T* accessorData(const tinygltf::Model& model, const tinygltf::Accessor& a, int components, int componentType) {
  if (a.bufferView < 0 || a.componentType != componentType) return nullptr;
  const auto& view = model.bufferViews[static_cast<std::size_t>(a.bufferView)];
  if (view.buffer < 0) return nullptr;
  const auto& buffer = model.buffers[static_cast<std::size_t>(view.buffer)];
  const std::size_t stride = view.byteStride ? view.byteStride : sizeof(T) * static_cast<std::size_t>(components);
  if (stride != sizeof(T) * static_cast<std::size_t>(components)) return nullptr;  // tightly packed only
  const std::size_t begin = view.byteOffset + a.byteOffset;
  const std::size_t bytes = a.count * stride;
  if (begin + bytes > buffer.data.size() || a.byteOffset + bytes > view.byteLength) return nullptr;
  return reinterpret_cast<const T*>(buffer.data.data() + begin);
}

}  // namespace

Result<std::unique_ptr<GltfModelRendererGL>> GltfModelRendererGL::load(const std::string& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  if (!loader.LoadBinaryFromFile(&model, &err, &warn, path)) {
    return makeError(path + ": not a readable glTF binary: " + (err.empty() ? "unknown error" : err));
  }
  auto program = ShaderProgramGL::create("globe.vert", "model.frag");
  if (!program) return program.forwardError();
  std::unique_ptr<GltfModelRendererGL> r(new GltfModelRendererGL());
  r->program_ = std::move(*program);
  // glTF Y-up Earth-fixed -> ECEF (the 3D Tiles y-up to z-up rotation): (x, y, z) -> (x, -z, y).
  glm::dmat4 yUpToZUp(1.0);
  yUpToZUp[1] = glm::dvec4(0, 0, 1, 0);
  yUpToZUp[2] = glm::dvec4(0, -1, 0, 0);
  // Walk the default scene's node tree.
  std::vector<std::pair<int, glm::dmat4>> stack;
  const int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (model.scenes.empty()) return makeError(path + ": no scene");
  for (int n : model.scenes[static_cast<std::size_t>(sceneIndex)].nodes) stack.push_back({n, yUpToZUp});
  while (!stack.empty()) {
    auto [index, parent] = stack.back();
    stack.pop_back();
    if (index < 0 || static_cast<std::size_t>(index) >= model.nodes.size()) return makeError(path + ": bad node index");
    const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(index)];
    const glm::dmat4 world = parent * nodeLocalMatrix(node);
    for (int c : node.children) stack.push_back({c, world});
    if (node.mesh < 0) continue;
    for (const tinygltf::Primitive& prim : model.meshes[static_cast<std::size_t>(node.mesh)].primitives) {
      if (prim.mode != TINYGLTF_MODE_TRIANGLES) continue;
      const auto pos = prim.attributes.find("POSITION");
      const auto uv = prim.attributes.find("TEXCOORD_0");
      if (pos == prim.attributes.end() || prim.indices < 0)
        return makeError(path + ": primitive without POSITION/indices");
      const auto& pa = model.accessors[static_cast<std::size_t>(pos->second)];
      const float* positions = accessorData<float>(model, pa, 3, TINYGLTF_COMPONENT_TYPE_FLOAT);
      const float* texCoords = nullptr;
      if (uv != prim.attributes.end()) {
        const auto& ta = model.accessors[static_cast<std::size_t>(uv->second)];
        if (ta.count != pa.count) return makeError(path + ": TEXCOORD_0 count differs from POSITION");
        texCoords = accessorData<float>(model, ta, 2, TINYGLTF_COMPONENT_TYPE_FLOAT);
      }
      if (!positions) return makeError(path + ": unsupported or out-of-bounds POSITION accessor");
      const auto& ia = model.accessors[static_cast<std::size_t>(prim.indices)];
      std::vector<std::uint32_t> indices(ia.count);
      if (const auto* i32 = accessorData<std::uint32_t>(model, ia, 1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
        std::memcpy(indices.data(), i32, indices.size() * 4);
      } else if (const auto* i16 = accessorData<std::uint16_t>(model, ia, 1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)) {
        for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = i16[i];
      } else {
        return makeError(path + ": unsupported or out-of-bounds index accessor");
      }
      for (std::uint32_t i : indices) {
        if (i >= pa.count) return makeError(path + ": index out of range");
      }
      std::vector<float> vertices;
      vertices.reserve(pa.count * 5);
      for (std::size_t v = 0; v < pa.count; ++v) {
        vertices.insert(vertices.end(), {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2],
                                         texCoords ? texCoords[2 * v] : 0.0f, texCoords ? texCoords[2 * v + 1] : 0.0f});
      }
      PrimitiveGL p;
      p.modelToEcef = world;
      p.indexCount = static_cast<GLsizei>(indices.size());
      glCreateVertexArrays(1, &p.vao);
      glCreateBuffers(1, &p.vbo);
      glCreateBuffers(1, &p.ibo);
      glNamedBufferStorage(p.vbo, static_cast<GLsizeiptr>(vertices.size() * 4), vertices.data(), 0);
      glNamedBufferStorage(p.ibo, static_cast<GLsizeiptr>(indices.size() * 4), indices.data(), 0);
      glVertexArrayVertexBuffer(p.vao, 0, p.vbo, 0, 5 * sizeof(float));
      glVertexArrayElementBuffer(p.vao, p.ibo);
      floatAttributeGL(p.vao, 0, 3, 0);
      floatAttributeGL(p.vao, 1, 2, 3 * sizeof(float));
      if (prim.material >= 0) {
        const auto& mat = model.materials[static_cast<std::size_t>(prim.material)];
        const auto& f = mat.pbrMetallicRoughness.baseColorFactor;
        if (f.size() == 4) p.baseColor = glm::vec4(glm::dvec4(f[0], f[1], f[2], f[3]));
        const int texIndex = mat.pbrMetallicRoughness.baseColorTexture.index;
        if (texIndex >= 0 && model.textures[static_cast<std::size_t>(texIndex)].source >= 0) {
          const auto& img =
              model.images[static_cast<std::size_t>(model.textures[static_cast<std::size_t>(texIndex)].source)];
          if (img.component == 4 && img.bits == 8 &&
              img.image.size() == static_cast<std::size_t>(img.width) * img.height * 4) {
            glCreateTextures(GL_TEXTURE_2D, 1, &p.texture);
            glTextureStorage2D(p.texture, 1, GL_RGBA8, img.width, img.height);
            glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
            glTextureSubImage2D(p.texture, 0, 0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, img.image.data());
            // Nearest: the sweep image's texels are gates and rays, shown as they are.
            glTextureParameteri(p.texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTextureParameteri(p.texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            glTextureParameteri(p.texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glTextureParameteri(p.texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
          }
        }
      }
      r->primitives_.push_back(p);
    }
  }
  if (r->primitives_.empty()) return makeError(path + ": no triangle primitives to draw");
  return r;
}

GltfModelRendererGL::~GltfModelRendererGL() {
  for (PrimitiveGL& p : primitives_) {
    if (p.vao) glDeleteVertexArrays(1, &p.vao);
    if (p.vbo) glDeleteBuffers(1, &p.vbo);
    if (p.ibo) glDeleteBuffers(1, &p.ibo);
    if (p.texture) glDeleteTextures(1, &p.texture);
  }
}

std::size_t GltfModelRendererGL::triangleCount() const {
  std::size_t n = 0;
  for (const PrimitiveGL& p : primitives_) n += static_cast<std::size_t>(p.indexCount) / 3;
  return n;
}

void GltfModelRendererGL::draw(const Camera& camera) const {
  program_.use();
  glUniform1i(program_.uniform("u_imagery"), 0);
  glUniform4f(program_.uniform("u_uvTransform"), 1.0f, 1.0f, 0.0f, 0.0f);
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  for (const PrimitiveGL& p : primitives_) {
    // The model's translation is subtracted from the eye in double; only the rotation and
    // the (local, <= ~500 km) vertex offsets pass through float.
    glm::dmat4 rotation = p.modelToEcef;
    rotation[3] = glm::dvec4(0, 0, 0, 1);
    const glm::dvec3 origin(p.modelToEcef[3]);
    const glm::mat4 mvp = glm::mat4(camera.modelViewProjectionRelativeTo(origin) * rotation);
    glUniformMatrix4fv(program_.uniform("u_mvp"), 1, GL_FALSE, glm::value_ptr(mvp));
    glUniform1i(program_.uniform("u_hasImagery"), p.texture ? 1 : 0);
    glUniform4fv(program_.uniform("u_baseColor"), 1, glm::value_ptr(p.baseColor));
    if (p.texture) glBindTextureUnit(0, p.texture);
    glBindVertexArray(p.vao);
    glDrawElements(GL_TRIANGLES, p.indexCount, GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
}

}  // namespace atmoglobe::engine
