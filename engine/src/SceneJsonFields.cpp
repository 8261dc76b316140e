#include "SceneJsonFields.h"

#include <atmoglobe/globe/Text.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

namespace atmoglobe::engine::scenejson {

std::string typeName(const json& v) {
  if (v.is_string()) return "string";
  if (v.is_number_integer()) return "integer";
  if (v.is_number()) return "number";
  if (v.is_boolean()) return "boolean";
  if (v.is_array()) return "array";
  if (v.is_object()) return "object";
  return "null";
}

std::string expected(const char* what, const json& got) {
  return std::string("expected ") + what + ", got " + typeName(got);
}

namespace {
// Optimal string alignment distance (insertions, deletions, substitutions and transpositions of
// neighbours, one edit each), case ignored.
std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = toLowerAscii(a[i - 1]) == toLowerAscii(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && toLowerAscii(a[i - 1]) == toLowerAscii(b[j - 2]) &&
          toLowerAscii(a[i - 2]) == toLowerAscii(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

std::string formatValue(const json& v) {
  if (v.is_number_float()) {
    std::ostringstream s;
    s << v.get<double>();
    return s.str();
  }
  return v.dump();
}

std::string formatBound(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

std::string rangeText(double lo, double hi, const char* units) {
  std::string t = formatBound(lo) + ".." + formatBound(hi);
  if (units && *units) t.append(" ").append(units);
  return t;
}
}  // namespace

std::string closestKey(std::string_view key, const std::vector<std::string>& allowed) {
  std::string best;
  std::size_t bestDistance = std::string::npos;
  for (const std::string& k : allowed) {
    const std::size_t d = editDistance(key, k);
    if (d < bestDistance) {
      bestDistance = d;
      best = k;
    }
  }
  const std::size_t limit = std::max<std::size_t>(1, key.size() / 3);
  return bestDistance <= limit ? best : std::string();
}

std::string pointerToken(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

std::string Object::where() const { return source_ + ": " + (pointer_.empty() ? std::string("/") : pointer_); }
std::string Object::where(std::string_view key) const { return source_ + ": " + pointer(key); }

Status Object::checkObject(const std::vector<std::string>& allowed) const {
  if (!value_.is_object()) return error(expected("an object", value_));
  for (auto it = value_.begin(); it != value_.end(); ++it) {
    if (std::find(allowed.begin(), allowed.end(), it.key()) != allowed.end()) continue;
    std::string message = std::string("unknown key \"").append(it.key()).append("\"");
    const std::string hint = closestKey(it.key(), allowed);
    if (!hint.empty()) {
      message.append(" (did you mean \"").append(hint).append("\"?)");
    } else {
      message += " (keys here:";
      for (const std::string& k : allowed) message.append(" ").append(k);
      message += ")";
    }
    return error(it.key(), message);
  }
  return Ok{};
}

Status Object::require(const char* key, const char* what) const {
  if (!value_.contains(key)) return error(std::string("needs \"") + key + "\" (" + what + ")");
  return Ok{};
}

Status Object::number(const char* key, double& out, double lo, double hi, const char* units) const {
  if (!value_.contains(key)) return Ok{};
  const json& v = value_.at(key);
  if (!v.is_number()) return error(key, expected("a number", v));
  const double d = v.get<double>();
  if (!std::isfinite(d) || d < lo || d > hi)
    return error(key, formatValue(v) + " is out of range " + rangeText(lo, hi, units));
  out = d;
  return Ok{};
}

Status Object::number(const char* key, float& out, double lo, double hi, const char* units) const {
  double d = out;
  if (auto st = number(key, d, lo, hi, units); !st) return st;
  out = static_cast<float>(d);
  return Ok{};
}

Status Object::integer(const char* key, int& out, long long lo, long long hi, const char* units) const {
  if (!value_.contains(key)) return Ok{};
  const json& v = value_.at(key);
  if (!v.is_number_integer()) return error(key, expected("an integer", v));
  const bool isUnsigned = v.is_number_unsigned();
  if ((isUnsigned && (v.get<unsigned long long>() > static_cast<unsigned long long>(hi) ||
                      static_cast<long long>(v.get<unsigned long long>()) < lo)) ||
      (!isUnsigned && (v.get<long long>() < lo || v.get<long long>() > hi)))
    return error(key, formatValue(v) + " is out of range " + std::to_string(lo) + ".." + std::to_string(hi) +
                          (units && *units ? std::string(" ") + units : std::string()));
  out = static_cast<int>(v.get<long long>());
  return Ok{};
}

Status Object::indices(const char* key, std::map<std::string, std::size_t>& out, long long hi) const {
  if (!value_.contains(key)) return Ok{};
  const json& v = value_.at(key);
  if (!v.is_object()) return error(key, expected("an object of dimension names to indices", v));
  const Object o = member(key);
  for (const auto& [name, index] : v.items()) {
    if (name.empty()) return o.error("a dimension name must not be empty");
    int i = 0;
    if (auto st = o.integer(name.c_str(), i, 0, hi); !st) return st;
    out[name] = static_cast<std::size_t>(i);
  }
  return Ok{};
}

Status Object::string(const char* key, std::string& out) const {
  if (!value_.contains(key)) return Ok{};
  const json& v = value_.at(key);
  if (!v.is_string()) return error(key, expected("a string", v));
  out = v.get<std::string>();
  return Ok{};
}

Status Object::choice(const char* key, std::string& out, std::initializer_list<const char*> choices) const {
  return choice(key, out, std::vector<const char*>(choices));
}

Status Object::choice(const char* key, std::string& out, const std::vector<const char*>& choices) const {
  std::string s = out;
  if (auto st = string(key, s); !st) return st;
  if (!value_.contains(key)) return Ok{};
  std::string list;
  for (const char* c : choices) {
    if (s == c) {
      out = s;
      return Ok{};
    }
    list += list.empty() ? "" : ", ";
    list += std::string("\"") + c + "\"";
  }
  return error(key, std::string("\"").append(s).append("\" is not one of ").append(list));
}

Status Object::boolean(const char* key, bool& out) const {
  if (!value_.contains(key)) return Ok{};
  const json& v = value_.at(key);
  if (!v.is_boolean()) return error(key, expected("true or false", v));
  out = v.get<bool>();
  return Ok{};
}

Status Object::numbers(const char* key, std::vector<double>& out, std::size_t minCount, std::size_t maxCount,
                       const char* form, double lo, double hi) const {
  if (!value_.contains(key)) return Ok{};
  const json& a = value_.at(key);
  if (!a.is_array()) return error(key, expected((std::string("an array ") + form).c_str(), a));
  if (a.size() < minCount || a.size() > maxCount)
    return error(key, std::string("expected ").append(form) + ", got " + std::to_string(a.size()) + " elements");
  std::vector<double> v;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string at = pointer(key) + "/" + std::to_string(i);
    if (!a[i].is_number()) return makeError(source_ + ": " + at + ": " + expected("a number", a[i]));
    const double d = a[i].get<double>();
    if (!std::isfinite(d) || d < lo || d > hi)
      return makeError(source_ + ": " + at + ": " + formatValue(a[i]) + " is out of range " + rangeText(lo, hi, ""));
    v.push_back(d);
  }
  out = std::move(v);
  return Ok{};
}

Status Object::color(const char* key, glm::vec3& out) const {
  std::vector<double> v;
  if (auto st = numbers(key, v, 3, 3, "[r, g, b] (0..1)", 0.0, 1.0); !st) return st;
  if (!v.empty()) out = glm::vec3(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
  return Ok{};
}

Status Object::array(const char* key) const {
  if (!value_.contains(key)) return Ok{};
  const json& v = value_.at(key);
  if (!v.is_array()) return error(key, expected("an array", v));
  return Ok{};
}

}  // namespace atmoglobe::engine::scenejson
