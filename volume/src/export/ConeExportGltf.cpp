// glTF 2.0 (GLB and JSON) and 3D Tiles encoders for the radar cones.
#include <atmoglobe/volume/ConeExport.h>

#include <atmoglobe/globe/Ellipsoid.h>

#include <nlohmann/json.hpp>

#include <cstring>

namespace atmoglobe::volume {

namespace {

using nlohmann::json;

constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// Appends raw bytes, 4-byte aligned at the start (accessor alignment rule).
std::size_t appendAligned(std::string& bin, const void* data, std::size_t size) {
  while (bin.size() % 4 != 0) bin.push_back('\0');
  const std::size_t offset = bin.size();
  bin.append(static_cast<const char*>(data), size);
  return offset;
}

std::string base64(std::string_view in) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t(std::uint8_t(in[i])) << 16) | (std::uint32_t(std::uint8_t(in[i + 1])) << 8) |
                            std::uint8_t(in[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < in.size()) {
    std::uint32_t v = std::uint32_t(std::uint8_t(in[i])) << 16;
    if (i + 1 < in.size()) v |= std::uint32_t(std::uint8_t(in[i + 1])) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < in.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

void putU32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

json matrixJson(const glm::dmat4& m) {
  json a = json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) a.push_back(m[c][r]);  // column-major, as glTF and 3D Tiles store it
  return a;
}

}  // namespace

glm::dmat4 gltfRootMatrix(const ConeScene& scene) {
  // glTF local (x, y, z) = (east, up, -north) -> ENU.
  glm::dmat4 localToEnu(0.0);
  localToEnu[0] = glm::dvec4(1, 0, 0, 0);   // x -> east
  localToEnu[1] = glm::dvec4(0, 0, 1, 0);   // y -> up
  localToEnu[2] = glm::dvec4(0, -1, 0, 0);  // z -> -north
  localToEnu[3] = glm::dvec4(0, 0, 0, 1);
  // ECEF -> Y-up world (X, Z, -Y): the inverse of the 3D Tiles y-up -> z-up rotation.
  glm::dmat4 ecefToYup(0.0);
  ecefToYup[0] = glm::dvec4(1, 0, 0, 0);   // X_ecef -> x
  ecefToYup[1] = glm::dvec4(0, 0, -1, 0);  // Y_ecef -> -z
  ecefToYup[2] = glm::dvec4(0, 1, 0, 0);   // Z_ecef -> y
  ecefToYup[3] = glm::dvec4(0, 0, 0, 1);
  return ecefToYup * scene.enuToEcef * localToEnu;
}

std::string encodeConesGltf(const ConeScene& scene, bool binary, bool withEcefMatrix) {
  json doc;
  doc["asset"] = {{"version", "2.0"}, {"generator", "atmoglobe export-cones"}};
  doc["extensionsUsed"] = json::array({"KHR_materials_unlit"});
  std::string bin;
  json bufferViews = json::array(), accessors = json::array(), meshes = json::array(), nodes = json::array();
  json materials = json::array(), textures = json::array(), images = json::array();
  json children = json::array();

  auto addView = [&](const void* data, std::size_t size, int target) {
    const std::size_t offset = appendAligned(bin, data, size);
    json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}};
    if (target) v["target"] = target;
    bufferViews.push_back(v);
    return bufferViews.size() - 1;
  };

  for (std::size_t i = 0; i < scene.cones.size(); ++i) {
    const Cone& cone = scene.cones[i];
    const ConeMesh& m = cone.mesh;
    // Positions stored Y-up: (east, up, -north). Float32 (see ConeMesh.h for the rounding bound).
    std::vector<float> pos;
    pos.reserve(m.positionsEnu.size() * 3);
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& p : m.positionsEnu) {
      const glm::vec3 g(p.x, p.z, -p.y);
      lo = glm::min(lo, g);
      hi = glm::max(hi, g);
      pos.insert(pos.end(), {g.x, g.y, g.z});
    }
    const std::size_t posView = addView(pos.data(), pos.size() * sizeof(float), kArrayBuffer);
    accessors.push_back({{"bufferView", posView},
                         {"componentType", kFloat},
                         {"count", m.positionsEnu.size()},
                         {"type", "VEC3"},
                         {"min", {lo.x, lo.y, lo.z}},
                         {"max", {hi.x, hi.y, hi.z}}});
    const std::size_t posAcc = accessors.size() - 1;
    const std::size_t uvView = addView(m.texCoords.data(), m.texCoords.size() * sizeof(glm::vec2), kArrayBuffer);
    accessors.push_back(
        {{"bufferView", uvView}, {"componentType", kFloat}, {"count", m.texCoords.size()}, {"type", "VEC2"}});
    const std::size_t uvAcc = accessors.size() - 1;
    const std::size_t idxView =
        addView(m.indices.data(), m.indices.size() * sizeof(std::uint32_t), kElementArrayBuffer);
    accessors.push_back(
        {{"bufferView", idxView}, {"componentType", kUnsignedInt}, {"count", m.indices.size()}, {"type", "SCALAR"}});
    const std::size_t idxAcc = accessors.size() - 1;

    const std::size_t imgView = addView(cone.png.data(), cone.png.size(), 0);
    const std::string name = sweepStem(cone.sweepIndex);
    images.push_back({{"bufferView", imgView}, {"mimeType", "image/png"}, {"name", name}});
    textures.push_back({{"sampler", 0}, {"source", images.size() - 1}});
    materials.push_back(
        {{"name", name},
         {"pbrMetallicRoughness",
          {{"baseColorTexture", {{"index", textures.size() - 1}}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
         {"alphaMode", "BLEND"},
         {"doubleSided", true},
         {"extensions", {{"KHR_materials_unlit", json::object()}}}});
    meshes.push_back({{"name", name},
                      {"primitives", json::array({{{"attributes", {{"POSITION", posAcc}, {"TEXCOORD_0", uvAcc}}},
                                                   {"indices", idxAcc},
                                                   {"material", materials.size() - 1},
                                                   {"mode", 4}}})}});
    char label[96];
    std::snprintf(label, sizeof label, "%s elevation %.2f deg", name.c_str(), m.elevationDeg);
    nodes.push_back({{"name", label}, {"mesh", meshes.size() - 1}});
    children.push_back(nodes.size() - 1);
  }

  json root = {{"name", scene.title.empty() ? std::string("radar cones") : scene.title}, {"children", children}};
  root["extras"] = {{"site_lat_deg", scene.site.site.latDeg},
                    {"site_lon_deg", scene.site.site.lonDeg},
                    {"antenna_height_ellipsoid_m", scene.site.site.antennaHeightEllipsoidMeters},
                    {"local_frame", "x east, y up, z south (ENU at the antenna, metres)"},
                    {"world_frame", withEcefMatrix ? "Y-up Earth-fixed: (X_ecef, Z_ecef, -Y_ecef)" : "local"},
                    {"beam", scene.straight ? "straight cone" : "effective Earth radius model"}};
  if (withEcefMatrix) root["matrix"] = matrixJson(gltfRootMatrix(scene));
  nodes.push_back(root);
  doc["nodes"] = nodes;
  doc["scenes"] = json::array({{{"nodes", json::array({nodes.size() - 1})}}});
  doc["scene"] = 0;
  if (!meshes.empty()) {
    doc["meshes"] = meshes;
    doc["accessors"] = accessors;
    doc["bufferViews"] = bufferViews;
    doc["materials"] = materials;
    doc["textures"] = textures;
    doc["images"] = images;
    // Nearest up close (gates stay crisp), linear when minified; clamp: no wrap across the seam.
    doc["samplers"] = json::array({{{"magFilter", 9728}, {"minFilter", 9729}, {"wrapS", 33071}, {"wrapT", 33071}}});
  }
  while (bin.size() % 4 != 0) bin.push_back('\0');
  if (!bin.empty()) {
    json buffer = {{"byteLength", bin.size()}};
    if (!binary) buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
    doc["buffers"] = json::array({buffer});
  }
  std::string text = doc.dump();
  if (!binary) return text;

  while (text.size() % 4 != 0) text.push_back(' ');
  std::string glb;
  glb.reserve(12 + 8 + text.size() + 8 + bin.size());
  putU32(glb, 0x46546C67);  // "glTF"
  putU32(glb, 2);
  putU32(glb, static_cast<std::uint32_t>(12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size())));
  putU32(glb, static_cast<std::uint32_t>(text.size()));
  putU32(glb, 0x4E4F534A);  // "JSON"
  glb += text;
  if (!bin.empty()) {
    putU32(glb, static_cast<std::uint32_t>(bin.size()));
    putU32(glb, 0x004E4942);  // "BIN\0"
    glb += bin;
  }
  return glb;
}

std::string encodeConesTileset(const ConeScene& scene, const std::string& contentUri) {
  // Bounding box in the tile frame (ENU after the y-up -> z-up rotation), from every cone.
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const Cone& c : scene.cones) {
    lo = glm::min(lo, glm::dvec3(c.mesh.minEnu));
    hi = glm::max(hi, glm::dvec3(c.mesh.maxEnu));
  }
  if (scene.cones.empty()) lo = hi = glm::dvec3(0.0);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const glm::dvec3 half = 0.5 * (hi - lo) + glm::dvec3(1.0);  // 1 m margin for float rounding
  json tileset;
  tileset["asset"] = {{"version", "1.1"}, {"generator", "atmoglobe export-cones"}};
  const double extent = 2.0 * glm::length(half);
  tileset["geometricError"] = extent;
  tileset["root"] = {
      {"transform", matrixJson(scene.enuToEcef)},
      {"boundingVolume", {{"box", {centre.x, centre.y, centre.z, half.x, 0, 0, 0, half.y, 0, 0, 0, half.z}}}},
      {"geometricError", 0.0},
      {"refine", "ADD"},
      {"content", {{"uri", contentUri}}}};
  return tileset.dump(2);
}

}  // namespace atmoglobe::volume
