// COLLADA 1.4.1 encoder for the radar cones (Z_UP, metres, ENU at the antenna).
#include <atmoglobe/volume/ConeExport.h>

#include <atmoglobe/globe/AtomicFile.h>

#include <cctype>
#include <charconv>
#include <cstdio>
#include <ctime>

namespace atmoglobe::volume {

namespace {

void appendFloat(std::string& s, float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest form that reads back exactly
  s.append(buf, r.ptr);
}

std::string xmlEscape(std::string_view in) {
  std::string out;
  for (char c : in) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // Control characters are not allowed in XML 1.0 text; drop them.
        if (static_cast<unsigned char>(c) >= 0x20 || c == '\t' || c == '\n') out += c;
    }
  }
  return out;
}

// COLLADA's name attributes are xs:NCName: letters, digits, '_', '-', '.', not starting with a
// digit, '-' or '.'. Anything else becomes '_'.
std::string ncName(std::string_view in) {
  std::string out;
  if (in.empty() || !(std::isalpha(static_cast<unsigned char>(in[0])) || in[0] == '_')) out.push_back('_');
  for (char c : in)
    out.push_back(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ? c : '_');
  return out;
}

std::string nowIso8601() {
  const std::time_t t = globe::outputTime();  // now, or $SOURCE_DATE_EPOCH (reproducible exports)
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace

std::string sweepStem(std::size_t sweepIndex) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "sweep%02zu", sweepIndex);
  return buf;
}

std::string encodeConesCollada(const ConeScene& scene, const std::vector<std::size_t>& cones,
                               const std::vector<std::string>& textureUris) {
  const std::string now = nowIso8601();
  std::string s;
  s += "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
  s += "<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n";
  s += "  <asset>\n    <contributor><authoring_tool>atmoglobe export-cones</authoring_tool>";
  s += "<comments>" + xmlEscape(scene.title) +
       "; local east-north-up frame at the antenna (m)</comments></contributor>\n";
  s += "    <created>" + now + "</created>\n    <modified>" + now + "</modified>\n";
  s += "    <unit name=\"meter\" meter=\"1\"/>\n    <up_axis>Z_UP</up_axis>\n  </asset>\n";

  s += "  <library_images>\n";
  for (std::size_t k = 0; k < cones.size(); ++k) {
    const std::string id = "img-" + sweepStem(scene.cones[cones[k]].sweepIndex);
    s += "    <image id=\"" + id + "\" name=\"" + id + "\"><init_from>" + xmlEscape(textureUris[k]) +
         "</init_from></image>\n";
  }
  s += "  </library_images>\n  <library_effects>\n";
  for (std::size_t k = 0; k < cones.size(); ++k) {
    const std::string stem = sweepStem(scene.cones[cones[k]].sweepIndex);
    s += "    <effect id=\"fx-" + stem + "\">\n      <profile_COMMON>\n";
    s += "        <newparam sid=\"surface-" + stem + "\"><surface type=\"2D\"><init_from>img-" + stem +
         "</init_from></surface></newparam>\n";
    s +=
        "        <newparam sid=\"sampler-" + stem + "\"><sampler2D><source>surface-" + stem +
        "</source><wrap_s>CLAMP</wrap_s><wrap_t>CLAMP</wrap_t><minfilter>LINEAR</minfilter><magfilter>NEAREST</magfilter></sampler2D></newparam>\n";
    s += "        <technique sid=\"common\">\n          <lambert>\n";
    s += "            <diffuse><texture texture=\"sampler-" + stem + "\" texcoord=\"UVSET0\"/></diffuse>\n";
    s += "            <transparent opaque=\"A_ONE\"><texture texture=\"sampler-" + stem +
         "\" texcoord=\"UVSET0\"/></transparent>\n";
    s += "          </lambert>\n";
    s += "          <extra><technique profile=\"GOOGLEEARTH\"><double_sided>1</double_sided></technique></extra>\n";
    s += "        </technique>\n      </profile_COMMON>\n";
    s += "      <extra><technique profile=\"MAX3D\"><double_sided>1</double_sided></technique></extra>\n";
    s += "    </effect>\n";
  }
  s += "  </library_effects>\n  <library_materials>\n";
  for (std::size_t k = 0; k < cones.size(); ++k) {
    const std::string stem = sweepStem(scene.cones[cones[k]].sweepIndex);
    s += "    <material id=\"mat-" + stem + "\" name=\"" + stem + "\"><instance_effect url=\"#fx-" + stem +
         "\"/></material>\n";
  }
  s += "  </library_materials>\n  <library_geometries>\n";
  for (std::size_t k = 0; k < cones.size(); ++k) {
    const Cone& cone = scene.cones[cones[k]];
    const ConeMesh& m = cone.mesh;
    const std::string g = "geom-" + sweepStem(cone.sweepIndex);
    const std::size_t n = m.positionsEnu.size();
    s += "    <geometry id=\"" + g + "\" name=\"" + sweepStem(cone.sweepIndex) + "\">\n      <mesh>\n";
    s += "        <source id=\"" + g + "-pos\"><float_array id=\"" + g + "-pos-array\" count=\"" +
         std::to_string(3 * n) + "\">";
    for (std::size_t i = 0; i < n; ++i) {
      const glm::vec3& p = m.positionsEnu[i];
      if (i) s += ' ';
      appendFloat(s, p.x);
      s += ' ';
      appendFloat(s, p.y);
      s += ' ';
      appendFloat(s, p.z);
    }
    s +=
        "</float_array>\n          <technique_common><accessor source=\"#" + g + "-pos-array\" count=\"" +
        std::to_string(n) +
        "\" stride=\"3\"><param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/><param name=\"Z\" type=\"float\"/></accessor></technique_common>\n        </source>\n";
    s += "        <source id=\"" + g + "-uv\"><float_array id=\"" + g + "-uv-array\" count=\"" + std::to_string(2 * n) +
         "\">";
    for (std::size_t i = 0; i < n; ++i) {
      if (i) s += ' ';
      appendFloat(s, m.texCoords[i].x);
      s += ' ';
      appendFloat(s, 1.0f - m.texCoords[i].y);  // COLLADA t runs up from the image's bottom row
    }
    s +=
        "</float_array>\n          <technique_common><accessor source=\"#" + g + "-uv-array\" count=\"" +
        std::to_string(n) +
        "\" stride=\"2\"><param name=\"S\" type=\"float\"/><param name=\"T\" type=\"float\"/></accessor></technique_common>\n        </source>\n";
    s += "        <vertices id=\"" + g + "-vtx\"><input semantic=\"POSITION\" source=\"#" + g + "-pos\"/></vertices>\n";
    s += "        <triangles material=\"material\" count=\"" + std::to_string(m.triangleCount()) + "\">\n";
    s += "          <input semantic=\"VERTEX\" source=\"#" + g + "-vtx\" offset=\"0\"/>\n";
    s += "          <input semantic=\"TEXCOORD\" source=\"#" + g + "-uv\" offset=\"1\" set=\"0\"/>\n          <p>";
    for (std::size_t i = 0; i < m.indices.size(); ++i) {
      if (i) s += ' ';
      const std::string v = std::to_string(m.indices[i]);
      s += v;
      s += ' ';
      s += v;
    }
    s += "</p>\n        </triangles>\n      </mesh>\n    </geometry>\n";
  }
  s += "  </library_geometries>\n  <library_visual_scenes>\n    <visual_scene id=\"scene\" name=\"" +
       ncName(scene.title) + "\">\n";
  for (std::size_t k = 0; k < cones.size(); ++k) {
    const Cone& cone = scene.cones[cones[k]];
    const std::string stem = sweepStem(cone.sweepIndex);
    char name[96];
    std::snprintf(name, sizeof name, "%s_elevation_%.2f_deg", stem.c_str(), cone.mesh.elevationDeg);
    s += "      <node id=\"node-" + stem + "\" name=\"" + ncName(name) + "\">\n";
    s += "        <instance_geometry url=\"#geom-" + stem +
         "\"><bind_material><technique_common>"
         "<instance_material symbol=\"material\" target=\"#mat-" +
         stem +
         "\"><bind_vertex_input semantic=\"UVSET0\" input_semantic=\"TEXCOORD\" input_set=\"0\"/></instance_material>"
         "</technique_common></bind_material></instance_geometry>\n      </node>\n";
  }
  s += "    </visual_scene>\n  </library_visual_scenes>\n";
  s += "  <scene><instance_visual_scene url=\"#scene\"/></scene>\n</COLLADA>\n";
  return s;
}

}  // namespace atmoglobe::volume
