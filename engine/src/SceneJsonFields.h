#pragma once
// Reading a scene's JSON objects strictly (engine-internal: Scene.cpp, SliceLayer.cpp): every
// message starts "SOURCE: /json/pointer: " (RFC 6901) and says what was expected and what was
// found; unknown keys are named with the closest known key as a hint.
#include <atmoglobe/engine/SliceLayer.h>
#include <atmoglobe/globe/Result.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <initializer_list>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::engine::scenejson {

using json = nlohmann::json;

/// "string", "integer", "number", "boolean", "array", "object" or "null".
std::string typeName(const json& value);

/// The allowed key closest to `key` (edit distance, case ignored) when it is close enough to be
/// a misspelling (distance <= max(1, length / 3)); empty otherwise.
std::string closestKey(std::string_view key, const std::vector<std::string>& allowed);

/// RFC 6901 escaping of one reference token ("~" -> "~0", "/" -> "~1").
std::string pointerToken(std::string_view key);

/// A JSON object at `pointer` (e.g. "/radars/2") of the scene named `source`.
class Object {
 public:
  Object(const json& value, std::string source, std::string pointer)
      : value_(value), source_(std::move(source)), pointer_(std::move(pointer)) {}

  const json& value() const { return value_; }
  const std::string& pointer() const { return pointer_; }
  /// "SOURCE: /pointer" (the object), or "SOURCE: /pointer/key" (one of its keys).
  std::string where() const;
  std::string where(std::string_view key) const;
  std::string pointer(std::string_view key) const { return pointer_ + "/" + pointerToken(key); }
  /// An error about the object or one of its keys.
  Status error(const std::string& problem) const { return makeError(where() + ": " + problem); }
  Status error(std::string_view key, const std::string& problem) const {
    return makeError(where(key) + ": " + problem);
  }

  /// The value is an object and every key is one of `allowed` (else: the first unknown key, with
  /// a hint).
  Status checkObject(const std::vector<std::string>& allowed) const;
  bool has(const char* key) const { return value_.contains(key); }
  Status require(const char* key, const char* what) const;

  /// Absent keys leave `out` as it is. Ranges are inclusive; `units` is said in range errors.
  Status number(const char* key, double& out, double lo, double hi, const char* units = "") const;
  Status number(const char* key, float& out, double lo, double hi, const char* units = "") const;
  Status integer(const char* key, int& out, long long lo, long long hi, const char* units = "") const;
  Status string(const char* key, std::string& out) const;
  /// A string from `choices` (the message lists them).
  Status choice(const char* key, std::string& out, std::initializer_list<const char*> choices) const;
  Status choice(const char* key, std::string& out, const std::vector<const char*>& choices) const;
  Status boolean(const char* key, bool& out) const;
  /// An array of minCount..maxCount numbers, each in lo..hi; `form` says it ("[min, max]").
  Status numbers(const char* key, std::vector<double>& out, std::size_t minCount, std::size_t maxCount,
                 const char* form, double lo = -1e300, double hi = 1e300) const;
  /// [r, g, b] in 0..1.
  Status color(const char* key, glm::vec3& out) const;
  /// An object of names to indices (a grid's "index": {"month": 3}), each in 0..hi.
  Status indices(const char* key, std::map<std::string, std::size_t>& out, long long hi) const;
  /// An array (each element visited by the caller with element(i)).
  Status array(const char* key) const;
  Object element(const char* key, std::size_t index) const {
    return Object(value_.at(key).at(index), source_, pointer(key) + "/" + std::to_string(index));
  }
  Object member(const char* key) const { return Object(value_.at(key), source_, pointer(key)); }

 private:
  const json& value_;
  std::string source_;
  std::string pointer_;
};

/// "expected a number, got string".
std::string expected(const char* what, const json& got);

}  // namespace atmoglobe::engine::scenejson

namespace atmoglobe::engine {
/// One element of a scene's "slices" (SliceLayer.cpp).
Status parseSliceLayer(const scenejson::Object& slice, const std::string& baseDir, const std::string& dataDir,
                       SliceLayerDescription& out);
}  // namespace atmoglobe::engine
