#include <atmoglobe/volume/RainbowReader.h>
#include "ReadUnwrapped.h"

#include <atmoglobe/globe/Text.h>
#include <atmoglobe/io/Compression.h>
#include <atmoglobe/volume/RadarReader.h>

#include <expat.h>
#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>

namespace atmoglobe::volume {

namespace {

constexpr const char* kEndXml = "<!-- END XML -->";

// ------------------------------------------------------------------ a small XML tree (expat)
struct Node {
  std::string name;
  std::map<std::string, std::string> attrs;
  std::string text;
  std::vector<std::unique_ptr<Node>> children;
  Node* parent = nullptr;

  const Node* child(const std::string& n) const {
    for (const auto& c : children)
      if (c->name == n) return c.get();
    return nullptr;
  }
  std::vector<const Node*> all(const std::string& n) const {
    std::vector<const Node*> out;
    for (const auto& c : children)
      if (c->name == n) out.push_back(c.get());
    return out;
  }
  std::optional<std::string> attr(const std::string& n) const {
    auto it = attrs.find(n);
    if (it == attrs.end()) return std::nullopt;
    return it->second;
  }
};

struct ParseState {
  std::unique_ptr<Node> root;
  Node* current = nullptr;
  std::size_t nodes = 0;
};

void XMLCALL onStart(void* user, const XML_Char* name, const XML_Char** atts) {
  auto* st = static_cast<ParseState*>(user);
  auto node = std::make_unique<Node>();
  node->name = name;
  for (std::size_t i = 0; atts[i] && atts[i + 1]; i += 2) node->attrs[atts[i]] = atts[i + 1];
  ++st->nodes;
  Node* raw = node.get();
  if (!st->current) {
    st->root = std::move(node);
  } else {
    raw->parent = st->current;
    st->current->children.push_back(std::move(node));
  }
  st->current = raw;
}
void XMLCALL onEnd(void* user, const XML_Char*) {
  auto* st = static_cast<ParseState*>(user);
  if (st->current) st->current = st->current->parent;
}
void XMLCALL onText(void* user, const XML_Char* s, int len) {
  auto* st = static_cast<ParseState*>(user);
  if (st->current && st->current->text.size() < 4096) st->current->text.append(s, static_cast<std::size_t>(len));
}

std::optional<double> toDouble(const std::optional<std::string>& s) {
  if (!s) return std::nullopt;
  const std::string t(trimAscii(*s));
  if (t.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end == t.c_str() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// ------------------------------------------------------------------ the reader
struct Blob {
  std::size_t offset = 0;  // first byte of the data
  std::size_t size = 0;
  std::string compression;
};

const char* unitsOf(const std::string& type) {
  static const std::map<std::string, const char*> units = {
      {"dBZ", "dBZ"},         {"dBuZ", "dBZ"},       {"dBZv", "dBZ"},   {"dBuZv", "dBZ"},   {"V", "m/s"},
      {"Vu", "m/s"},          {"Vv", "m/s"},         {"Vvu", "m/s"},    {"W", "m/s"},       {"Wu", "m/s"},
      {"Wv", "m/s"},          {"Wvu", "m/s"},        {"ZDR", "dB"},     {"ZDRu", "dB"},     {"LDR", "dB"},
      {"PhiDP", "degrees"},   {"uPhiDP", "degrees"}, {"KDP", "deg/km"}, {"uKDP", "deg/km"}, {"RhoHV", "unitless"},
      {"uRhoHV", "unitless"}, {"SQI", "unitless"},   {"SNR", "dB"}};
  auto it = units.find(type);
  return it == units.end() ? "" : it->second;
}
const char* standardNameOf(const std::string& type) {
  static const std::map<std::string, const char*> names = {
      {"dBZ", "equivalent_reflectivity_factor"}, {"V", "radial_velocity_of_scatterers_away_from_instrument"},
      {"W", "doppler_spectrum_width"},           {"ZDR", "log_differential_reflectivity_hv"},
      {"PhiDP", "differential_phase_hv"},        {"KDP", "specific_differential_phase_hv"},
      {"RhoHV", "cross_correlation_ratio_hv"}};
  auto it = names.find(type);
  return it == names.end() ? "" : it->second;
}

class Reader {
 public:
  Reader(const std::string& label, const std::vector<unsigned char>& bytes, const ReadOptions& options)
      : label_(label), b_(bytes), options_(options) {}
  Result<RadarVolume> read();

 private:
  Error fail(const std::string& what) const { return makeError(label_ + ": Rainbow 5 " + what); }
  Status indexBlobs(std::size_t from);
  /// The BLOB's data, inflated; `expected` bytes exactly.
  Result<std::vector<unsigned char>> blob(long id, std::size_t expected, const std::string& what) const;
  /// A slice setting: the slice's own, else slice 0's, else the pargroup's.
  std::optional<std::string> setting(const Node* slice, const std::string& name) const {
    for (const Node* n : {slice, slice0_, pargroup_}) {
      if (!n) continue;
      if (const Node* c = n->child(name)) return std::string(trimAscii(c->text));
    }
    return std::nullopt;
  }

  std::string label_;
  const std::vector<unsigned char>& b_;
  ReadOptions options_;
  std::map<long, Blob> blobs_;
  const Node* slice0_ = nullptr;
  const Node* pargroup_ = nullptr;
};

Status Reader::indexBlobs(std::size_t pos) {
  const std::string open = "<BLOB";
  const auto* data = reinterpret_cast<const char*>(b_.data());
  while (true) {
    const char* hit = std::search(data + pos, data + b_.size(), open.begin(), open.end());
    if (hit == data + b_.size()) return Ok{};
    const std::size_t start = static_cast<std::size_t>(hit - data);
    const char* gt = std::find(hit, std::min(data + b_.size(), hit + 512), '>');
    if (gt == data + b_.size() || *gt != '>')
      return fail("BLOB at byte " + std::to_string(start) + ": header not closed");
    // Parse the header's attributes with expat, closing the element ourselves.
    std::string header(hit, gt + 1);
    header += "</BLOB>";
    ParseState st;
    XML_Parser p = XML_ParserCreate("ISO-8859-1");
    XML_SetUserData(p, &st);
    XML_SetElementHandler(p, onStart, onEnd);
    const bool ok = XML_Parse(p, header.data(), static_cast<int>(header.size()), 1) == XML_STATUS_OK;
    XML_ParserFree(p);
    if (!ok || !st.root) return fail("BLOB at byte " + std::to_string(start) + ": unreadable header");
    const auto id = toDouble(st.root->attr("blobid"));
    const auto size = toDouble(st.root->attr("size"));
    if (!id || !size || *size < 0 || *id < 0)
      return fail("BLOB at byte " + std::to_string(start) + ": no blobid/size attribute");
    std::size_t dataStart = static_cast<std::size_t>(gt - data) + 1;
    if (dataStart < b_.size() && b_[dataStart] == '\n') ++dataStart;
    const auto bytes = static_cast<std::size_t>(*size);
    if (bytes > b_.size() - std::min(dataStart, b_.size()))
      return fail("BLOB " + std::to_string(static_cast<long>(*id)) + " claims " + std::to_string(bytes) +
                  " bytes but only " + std::to_string(b_.size() - std::min(dataStart, b_.size())) +
                  " remain (truncated file?)");
    blobs_[static_cast<long>(*id)] = {dataStart, bytes, st.root->attr("compression").value_or("none")};
    pos = dataStart + bytes;
  }
}

Result<std::vector<unsigned char>> Reader::blob(long id, std::size_t expected, const std::string& what) const {
  auto it = blobs_.find(id);
  if (it == blobs_.end()) return fail(what + ": BLOB " + std::to_string(id) + " is not in the file");
  const Blob& bl = it->second;
  const unsigned char* p = b_.data() + bl.offset;
  std::vector<unsigned char> out;
  if (bl.compression == "qt") {
    if (bl.size < 4) return fail(what + ": BLOB " + std::to_string(id) + " too short for its qCompress size");
    const std::size_t usize = (std::size_t{p[0]} << 24) | (std::size_t{p[1]} << 16) | (std::size_t{p[2]} << 8) | p[3];
    if (usize != expected)
      return fail(what + ": BLOB " + std::to_string(id) + " inflates to " + std::to_string(usize) +
                  " bytes, the description needs " + std::to_string(expected));
    // zlib's deflate compresses at most 1032:1 (zlib FAQ), so a header claiming more than that
    // from this BLOB's bytes is corrupt: refused before allocating what it claims.
    if (usize / 1032 > bl.size - 4)
      return fail(what + ": BLOB " + std::to_string(id) + " claims " + std::to_string(usize) + " bytes from " +
                  std::to_string(bl.size - 4) + " compressed bytes (more than zlib's 1032:1)");
    out.resize(usize);
    uLongf produced = static_cast<uLongf>(usize);
    const int rc = uncompress(out.data(), &produced, p + 4, static_cast<uLong>(bl.size - 4));
    if (rc != Z_OK || produced != usize)
      return fail(what + ": BLOB " + std::to_string(id) + ": corrupt zlib data (" +
                  (rc == Z_OK ? std::string("short") : std::string(zError(rc))) + ")");
  } else if (bl.compression == "none" || bl.compression.empty()) {
    if (bl.size != expected)
      return fail(what + ": BLOB " + std::to_string(id) + " holds " + std::to_string(bl.size) +
                  " bytes, the description needs " + std::to_string(expected));
    out.assign(p, p + bl.size);
  } else {
    return fail(what + ": BLOB " + std::to_string(id) + " has unknown compression '" + bl.compression + "'");
  }
  return out;
}

Result<RadarVolume> Reader::read() {
  const auto* data = reinterpret_cast<const char*>(b_.data());
  const std::string marker = kEndXml;
  const char* endXml = std::search(data, data + b_.size(), marker.begin(), marker.end());
  if (endXml == data + b_.size()) return fail("file: no \"<!-- END XML -->\" after the XML header (truncated?)");
  const std::size_t xmlBytes = static_cast<std::size_t>(endXml - data);
  ParseState st;
  XML_Parser parser = XML_ParserCreate("ISO-8859-1");  // Rainbow writes Latin-1 comments without a declaration
  XML_SetUserData(parser, &st);
  XML_SetElementHandler(parser, onStart, onEnd);
  XML_SetCharacterDataHandler(parser, onText);
  const bool ok = XML_Parse(parser, data, static_cast<int>(xmlBytes), 1) == XML_STATUS_OK;
  std::string xmlError = ok ? "" : XML_ErrorString(XML_GetErrorCode(parser));
  const auto line = XML_GetCurrentLineNumber(parser);
  XML_ParserFree(parser);
  if (!ok) return fail("XML header: " + xmlError + " at line " + std::to_string(line));
  const Node* volume = st.root.get();
  if (!volume || volume->name != "volume") return fail("XML header: the root element is not <volume>");
  const std::string type = volume->attr("type").value_or("vol");
  SweepMode mode;
  if (type == "vol" || type == "azi") mode = SweepMode::Ppi;
  else if (type == "ele") mode = SweepMode::Rhi;
  else return fail("volume of type '" + type + "' is not supported (only vol, azi: PPI; ele: RHI)");
  const Node* scan = volume->child("scan");
  if (!scan) return fail("XML header: no <scan>");
  pargroup_ = scan->child("pargroup");
  const std::vector<const Node*> slices = scan->all("slice");
  if (slices.empty()) return fail("XML header: no <slice>");
  slice0_ = slices.front();
  if (Status s = indexBlobs(xmlBytes + marker.size()); !s) return s.forwardError();

  RadarVolume vol;
  vol.format = "Rainbow 5";
  vol.sourcePath = label_;
  const Node* sensor = volume->child("sensorinfo");
  if (!sensor) sensor = volume->child("radarinfo");
  if (!sensor) return fail("XML header: no <sensorinfo> or <radarinfo>: the file does not give the radar site");
  auto sensorValue = [&](const std::string& n) -> std::optional<double> {
    if (const Node* c = sensor->child(n)) return toDouble(c->text);
    return toDouble(sensor->attr(n));
  };
  const auto lat = sensorValue("lat"), lon = sensorValue("lon"), alt = sensorValue("alt");
  if (!lat || !lon || std::abs(*lat) > 90 || std::abs(*lon) > 360)
    return fail("<" + sensor->name + ">: no valid lat/lon");
  vol.site.latDeg = *lat;
  vol.site.lonDeg = *lon > 180 ? *lon - 360 : *lon;
  vol.site.antennaHeightMeters = alt.value_or(0.0);
  vol.site.heightDatum = HeightDatum::MeanSeaLevel;
  vol.site.name = sensor->attr("id").value_or(sensor->attr("name").value_or(""));
  if (const auto name = sensor->attr("name"); name && *name != vol.site.name) vol.site.placeName = *name;
  if (const auto bw = sensorValue("beamwidth"); bw && *bw > 0 && *bw < 20) vol.beamWidthDeg = *bw;
  const std::string date = scan->attr("date").value_or(""), time = scan->attr("time").value_or("");
  vol.timeIso8601 = normalizeIso8601(date + "T" + time);
  if (vol.timeIso8601.empty()) vol.timeIso8601 = normalizeIso8601(volume->attr("datetime").value_or(""));

  // Fields: every rawdata type, in order of first appearance.
  for (const Node* s : slices) {
    const Node* sd = s->child("slicedata");
    if (!sd) continue;
    for (const Node* raw : sd->all("rawdata")) {
      const std::string t = raw->attr("type").value_or("");
      if (t.empty()) continue;
      if (std::none_of(vol.fields.begin(), vol.fields.end(), [&](const FieldInfo& f) { return f.name == t; }))
        vol.fields.push_back({t, unitsOf(t), standardNameOf(t)});
      if (t == "V") {
        if (const auto mx = toDouble(raw->attr("max"))) {
          const double ny = std::abs(*mx);
          vol.nyquistVelocityMps = std::isfinite(vol.nyquistVelocityMps) ? std::max(vol.nyquistVelocityMps, ny) : ny;
        }
      }
    }
  }
  if (vol.fields.empty()) return fail("XML header: no <rawdata> in any slice");
  std::string loaded;
  if (options_.loadValues || !options_.fieldName.empty()) {
    auto idx = selectField(vol.fields, options_.fieldName);
    if (!idx) return makeError(label_ + ": " + idx.error());
    loaded = vol.fields[*idx].name;
    if (options_.loadValues) vol.loadedField = vol.fields[*idx];
  }

  for (std::size_t si = 0; si < slices.size(); ++si) {
    const Node* s = slices[si];
    const std::string where = "slice " + std::to_string(si);
    const Node* sd = s->child("slicedata");
    if (!sd) return fail(where + ": no <slicedata>");
    const auto posangle = toDouble(setting(s, "posangle"));
    const auto rangestep = toDouble(setting(s, "rangestep"));
    const double startRange = toDouble(setting(s, "start_range")).value_or(0.0);
    const double anglestep = toDouble(setting(s, "anglestep")).value_or(1.0);
    const bool ccw = toDouble(setting(s, "antdirection")).value_or(0.0) != 0.0;
    if (!posangle || !rangestep || *rangestep <= 0)
      return fail(where + ": no posangle or rangestep (nor in slice 0 or the pargroup)");
    // posangle: the elevation of a PPI (azi, vol), the azimuth of an RHI (ele).
    if (mode == SweepMode::Ppi ? std::abs(*posangle) > 90.0 : std::abs(*posangle) > 360.0)
      return fail(where + ": posangle " + std::to_string(*posangle) + " is outside " +
                  (mode == SweepMode::Ppi ? "[-90, 90] (a PPI elevation)" : "[-360, 360] (an RHI azimuth)"));
    const Node* startInfo = nullptr;
    const Node* stopInfo = nullptr;
    for (const Node* ri : sd->all("rayinfo")) {
      if (ri->attr("refid") == std::optional<std::string>("startangle")) startInfo = ri;
      if (ri->attr("refid") == std::optional<std::string>("stopangle")) stopInfo = ri;
    }
    if (!startInfo) return fail(where + ": no <rayinfo refid=\"startangle\">");
    auto angles = [&](const Node* ri) -> Result<std::vector<double>> {
      const auto id = toDouble(ri->attr("blobid")), rays = toDouble(ri->attr("rays")),
                 depth = toDouble(ri->attr("depth"));
      if (!id || !rays || !depth || *rays < 1 || *rays > 100000 || (*depth != 8 && *depth != 16))
        return fail(where + ": rayinfo needs blobid, rays (1..100000) and depth 8 or 16");
      const std::size_t n = static_cast<std::size_t>(*rays), w = static_cast<std::size_t>(*depth) / 8;
      auto bytes = blob(static_cast<long>(*id), n * w, where + " ray angles");
      if (!bytes) return bytes.forwardError();
      std::vector<double> out(n);
      const double scale = 360.0 / std::pow(2.0, *depth);
      for (std::size_t i = 0; i < n; ++i)
        out[i] = (w == 2 ? ((*bytes)[2 * i] << 8) | (*bytes)[2 * i + 1] : (*bytes)[i]) * scale;
      return out;
    };
    auto start = angles(startInfo);
    if (!start) return start.forwardError();
    std::optional<std::vector<double>> stop;
    if (stopInfo) {
      auto s2 = angles(stopInfo);
      if (!s2) return s2.forwardError();
      if (s2->size() != start->size()) return fail(where + ": start and stop angle counts differ");
      stop = std::move(*s2);
    }
    const std::size_t rays = start->size();

    Sweep sw;
    sw.indexInFile = static_cast<int>(si);
    sw.mode = mode;
    sw.fixedAngleDeg = *posangle;
    sw.gateSpacingMeters = *rangestep * 1000.0;
    sw.firstGateRangeMeters = startRange * 1000.0 + sw.gateSpacingMeters / 2.0;
    for (std::size_t i = 0; i < rays; ++i) {
      double a;
      if (stop) {
        double d = (*stop)[i] - (*start)[i];
        if (d > 180) d -= 360;
        if (d < -180) d += 360;
        a = (*start)[i] + d / 2;
      } else {
        a = (*start)[i] + (ccw ? -anglestep : anglestep) / 2;
      }
      if (mode == SweepMode::Ppi) {
        a = std::fmod(a + 360.0, 360.0);
        sw.azimuthDeg.push_back(static_cast<float>(a));
        sw.elevationDeg.push_back(static_cast<float>(*posangle));
      } else {
        sw.azimuthDeg.push_back(static_cast<float>(*posangle));
        sw.elevationDeg.push_back(static_cast<float>(a > 180 ? a - 360 : a));
      }
    }
    // Gate count: the largest rawdata bins of the slice (every moment of a slice has the same).
    const Node* chosen = nullptr;
    std::uint32_t bins = 0;
    for (const Node* raw : sd->all("rawdata")) {
      const auto b = toDouble(raw->attr("bins"));
      if (!b || *b < 1 || *b > 100000) return fail(where + ": rawdata without a bins count in 1..100000");
      bins = std::max(bins, static_cast<std::uint32_t>(*b));
      if (raw->attr("type").value_or("") == loaded) chosen = raw;
    }
    sw.gateCount = bins;
    if (options_.loadValues) {
      // Every gate takes at least one byte once inflated, and zlib inflates at most 1032:1: a slice
      // claiming more gates than that from the whole file is refused before allocating for them.
      const std::size_t gates = rays * std::size_t{bins}, canHold = b_.size() * 1032;
      if (gates > canHold)
        return fail(where + " claims " + std::to_string(gates) + " gates (" + std::to_string(rays) + " rays x " +
                    std::to_string(bins) + " bins), more than a file of " + std::to_string(b_.size()) +
                    " bytes can hold");
      sw.values.assign(rays * bins, kNoData);
      if (chosen) {
        const auto id = toDouble(chosen->attr("blobid")), depth = toDouble(chosen->attr("depth"));
        const auto rrays = toDouble(chosen->attr("rays")), rbins = toDouble(chosen->attr("bins"));
        const auto vmin = toDouble(chosen->attr("min")), vmax = toDouble(chosen->attr("max"));
        if (!id || !depth || !rrays || !vmin || !vmax || (*depth != 8 && *depth != 16))
          return fail(where + ": rawdata " + loaded + " needs blobid, rays, bins, min, max and depth 8 or 16");
        if (static_cast<std::size_t>(*rrays) != rays)
          return fail(where + ": rawdata " + loaded + " has " + std::to_string(static_cast<long>(*rrays)) +
                      " rays, the ray angles " + std::to_string(rays));
        const std::size_t w = static_cast<std::size_t>(*depth) / 8, nb = static_cast<std::size_t>(*rbins);
        auto bytes = blob(static_cast<long>(*id), rays * nb * w, where + " " + loaded);
        if (!bytes) return bytes.forwardError();
        const double step = (*vmax - *vmin) / (std::pow(2.0, *depth) - 2.0);
        for (std::size_t r = 0; r < rays; ++r) {
          for (std::size_t g = 0; g < nb; ++g) {
            const std::size_t k = r * nb + g;
            const unsigned raw = w == 2 ? ((*bytes)[2 * k] << 8) | (*bytes)[2 * k + 1] : (*bytes)[k];
            sw.values[r * bins + g] = raw == 0 ? kNoEcho : static_cast<float>(*vmin + (raw - 1.0) * step);
          }
        }
      }
    }
    vol.sweeps.push_back(std::move(sw));
  }
  std::stable_sort(vol.sweeps.begin(), vol.sweeps.end(),
                   [](const Sweep& a, const Sweep& c) { return a.fixedAngleDeg < c.fixedAngleDeg; });
  return vol;
}

}  // namespace

bool looksLikeRainbow5(const unsigned char* bytes, std::size_t size) {
  std::size_t i = 0;
  while (i < size && (bytes[i] == ' ' || bytes[i] == '\n' || bytes[i] == '\r' || bytes[i] == '\t')) ++i;
  return size - i >= 8 && std::memcmp(bytes + i, "<volume", 7) == 0 &&
         (bytes[i + 7] == ' ' || bytes[i + 7] == '>' || bytes[i + 7] == '\n' || bytes[i + 7] == '\t');
}

Result<RadarVolume> readRainbow5(const std::string& label, const std::vector<unsigned char>& bytes,
                                 const ReadOptions& options) {
  if (!looksLikeRainbow5(bytes.data(), bytes.size()))
    return makeError(label + ": not a Rainbow 5 volume (no <volume>)");
  return Reader(label, bytes, options).read();
}

Result<RadarVolume> readRainbow5(const std::string& path, const ReadOptions& options) {
  return readUnwrapped(path, options,
                       [](const std::string& label, const std::vector<unsigned char>& bytes, const ReadOptions& o) {
                         return readRainbow5(label, bytes, o);
                       });
}

}  // namespace atmoglobe::volume
