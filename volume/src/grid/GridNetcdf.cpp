// The grid reader's netCDF layer: groups, attributes, CF packing, and reads of picked indices
// through as few hyperslabs as the picks allow.
#include "GridInternal.h"

#include <atmoglobe/globe/Text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <utility>

namespace atmoglobe::volume::grid {

std::vector<int> allGroups(const io::NetcdfFile& f) {
  std::vector<int> out;
  std::vector<int> stack{f.root()};
  while (!stack.empty()) {
    const int g = stack.back();
    stack.pop_back();
    out.push_back(g);
    const std::vector<std::string> names = f.childGroupNames(g);
    for (auto it = names.rbegin(); it != names.rend(); ++it)
      if (auto child = f.findGroup(g, *it)) stack.push_back(*child);
  }
  return out;
}

std::optional<int> parentGroup(int group) {
  const io::NetcdfLock lock;
  int parent = -1;
  if (nc_inq_grp_parent(group, &parent) != NC_NOERR) return std::nullopt;
  return parent;
}

std::string dimensionName(int group, int dimId) {
  const io::NetcdfLock lock;
  char buf[NC_MAX_NAME + 1] = {};
  if (nc_inq_dimname(group, dimId, buf) != NC_NOERR) return "?";
  return buf;
}

std::string attrText(const io::NetcdfFile& f, const io::NcVar& v, const char* name) {
  if (!f.hasAttribute(v.groupId, v.varId, name)) return {};
  auto s = f.attributeString(v.groupId, v.varId, name);
  return s ? *s : std::string();
}

std::string globalText(const io::NetcdfFile& f, const char* name) {
  if (!f.hasAttribute(f.root(), NC_GLOBAL, name)) return {};
  auto s = f.attributeString(f.root(), NC_GLOBAL, name);
  return s ? *s : std::string();
}

Error varError(const io::NetcdfFile& f, const io::NcVar& v, const std::string& what) {
  return makeError(f.message("variable '" + v.name + "': " + what));
}

std::string num(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::optional<io::NcVar> findInScope(const io::NetcdfFile& f, int group, const std::string& name) {
  std::optional<int> g = group;
  while (g) {
    if (auto v = f.findVariable(*g, name)) return v;
    g = parentGroup(*g);
  }
  return std::nullopt;
}

const char* typeName(nc_type t) {
  switch (t) {
    case NC_BYTE: return "byte";
    case NC_UBYTE: return "ubyte";
    case NC_CHAR: return "char";
    case NC_SHORT: return "short";
    case NC_USHORT: return "ushort";
    case NC_INT: return "int";
    case NC_UINT: return "uint";
    case NC_INT64: return "int64";
    case NC_UINT64: return "uint64";
    case NC_FLOAT: return "float";
    case NC_DOUBLE: return "double";
    case NC_STRING: return "string";
    default: return "other";
  }
}

namespace {
bool isSignedInteger(nc_type t) { return t == NC_BYTE || t == NC_SHORT || t == NC_INT || t == NC_INT64; }
}  // namespace

Result<Packing> packingOf(const io::NetcdfFile& f, const io::NcVar& v) {
  Packing p;
  const int g = v.groupId, id = v.varId;
  auto one = [&](const char* name, double* out) -> Status {
    auto r = f.attributeDouble(g, id, name);
    if (!r) return r.forwardError();
    if (!std::isfinite(*r) && std::string(name) != "_FillValue" && std::string(name) != "missing_value")
      return makeError(f.message("attribute '" + v.name + ":" + name + "' is not a finite number"));
    *out = *r;
    return Ok{};
  };
  if (f.hasAttribute(g, id, "scale_factor"))
    if (auto st = one("scale_factor", &p.scale); !st) return st.forwardError();
  if (f.hasAttribute(g, id, "add_offset"))
    if (auto st = one("add_offset", &p.offset); !st) return st.forwardError();
  if (f.hasAttribute(g, id, "_FillValue")) {
    if (auto st = one("_FillValue", &p.fill); !st) return st.forwardError();
    p.hasFill = true;
  }
  if (f.hasAttribute(g, id, "missing_value")) {
    auto r = f.attributeDoubles(g, id, "missing_value", 16);
    if (!r) return r.forwardError();
    p.missing = *r;
  }
  if (f.hasAttribute(g, id, "valid_range")) {
    auto r = f.attributeDoubles(g, id, "valid_range", 2);
    if (!r) return r.forwardError();
    if (r->size() != 2 || !((*r)[0] <= (*r)[1]))
      return makeError(f.message("attribute '" + v.name + ":valid_range' must hold two values, min <= max"));
    p.validMin = (*r)[0];
    p.validMax = (*r)[1];
  }
  if (f.hasAttribute(g, id, "valid_min"))
    if (auto st = one("valid_min", &p.validMin); !st) return st.forwardError();
  if (f.hasAttribute(g, id, "valid_max"))
    if (auto st = one("valid_max", &p.validMax); !st) return st.forwardError();
  if (isSignedInteger(v.type) && f.hasAttribute(g, id, "_Unsigned")) {
    const std::string u = toLowerAscii(attrText(f, v, "_Unsigned"));
    if (u == "true") {
      p.isUnsigned = true;
      p.unsignedWrap = std::ldexp(1.0, static_cast<int>(8 * io::ncTypeSize(v.type)));
      auto wrap = [&](double& x) {
        if (x < 0) x += p.unsignedWrap;
      };
      wrap(p.fill);
      for (double& m : p.missing) wrap(m);
      if (std::isfinite(p.validMin)) wrap(p.validMin);
      if (std::isfinite(p.validMax)) wrap(p.validMax);
    }
  }
  if (!p.hasFill && (v.type == NC_FLOAT || v.type == NC_DOUBLE)) {
    p.defaultFloatFill = true;
    p.defaultFill = v.type == NC_FLOAT ? static_cast<double>(NC_FILL_FLOAT) : NC_FILL_DOUBLE;
  }
  return p;
}

std::vector<std::size_t> iota(std::size_t first, std::size_t n) {
  std::vector<std::size_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = first + i;
  return v;
}

namespace {

struct Run {
  std::size_t start = 0, count = 0;
  std::ptrdiff_t stride = 1;
  std::vector<std::size_t> outPos;  ///< output position of each element of the run
};

/// Splits picks into maximal arithmetic runs of increasing file index.
std::vector<Run> runsOf(const std::vector<std::size_t>& picks) {
  std::vector<std::pair<std::size_t, std::size_t>> s(picks.size());
  for (std::size_t o = 0; o < picks.size(); ++o) s[o] = {picks[o], o};
  std::sort(s.begin(), s.end());
  std::vector<Run> runs;
  std::size_t i = 0;
  while (i < s.size()) {
    Run r;
    r.start = s[i].first;
    r.outPos.push_back(s[i].second);
    std::size_t j = i + 1;
    if (j < s.size() && s[j].first > s[i].first) {
      const std::size_t step = s[j].first - s[i].first;
      r.stride = static_cast<std::ptrdiff_t>(step);
      while (j < s.size() && s[j].first - s[j - 1].first == step) r.outPos.push_back(s[j++].second);
    }
    r.count = r.outPos.size();
    runs.push_back(std::move(r));
    i = j;
  }
  return runs;
}

bool inOrder(const Run& r) {
  for (std::size_t m = 0; m < r.outPos.size(); ++m)
    if (r.outPos[m] != m) return false;
  return true;
}

template <class Out, class T>
Status readRuns(const io::NetcdfFile& f, const io::NcVar& v, const std::vector<std::vector<Run>>& runs,
                const std::vector<std::size_t>& outShape, const Packing& p, std::vector<Out>& out) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto decode = [&p, nan](double raw) -> Out {
    if (p.isUnsigned && raw < 0) raw += p.unsignedWrap;
    if (std::isnan(raw)) return static_cast<Out>(nan);
    if (p.hasFill && raw == p.fill) return static_cast<Out>(nan);
    if (p.defaultFloatFill && raw == p.defaultFill) return static_cast<Out>(nan);
    for (double m : p.missing)
      if (raw == m) return static_cast<Out>(nan);
    if (raw < p.validMin || raw > p.validMax) return static_cast<Out>(nan);
    return static_cast<Out>(raw * p.scale + p.offset);
  };
  const std::size_t rank = runs.size();
  std::vector<std::size_t> outStride(rank, 1);
  for (std::size_t d = rank; d-- > 1;) outStride[d - 1] = outStride[d] * outShape[d];

  // Fast path: one run per dimension, already in output order -> one read, no scatter.
  bool direct = true;
  for (const auto& r : runs) direct = direct && r.size() == 1 && inOrder(r[0]);
  std::vector<std::size_t> runIndex(rank, 0);
  std::unique_ptr<T[]> raw;
  std::size_t rawCapacity = 0;
  while (true) {
    std::vector<std::size_t> start(rank), count(rank);
    std::vector<std::ptrdiff_t> stride(rank);
    std::size_t n = 1;
    for (std::size_t d = 0; d < rank; ++d) {
      const Run& r = runs[d][runIndex[d]];
      start[d] = r.start;
      count[d] = r.count;
      stride[d] = r.stride;
      n *= r.count;
    }
    if (n > rawCapacity) {
      raw.reset(new T[n]);  // uninitialised: the read fills it
      rawCapacity = n;
    }
    if (auto st = f.readSlab<T>(v, start, count, stride, raw.get()); !st) return st;
    if (direct) {
      for (std::size_t i = 0; i < n; ++i) out[i] = decode(static_cast<double>(raw[i]));
      return Ok{};
    }
    // Scatter the block: odometer over all but the last dimension, inner loop over the last.
    std::vector<std::size_t> m(rank, 0);
    const std::size_t inner = rank == 0 ? 1 : count[rank - 1];
    const std::vector<std::size_t>* innerPos = rank == 0 ? nullptr : &runs[rank - 1][runIndex[rank - 1]].outPos;
    for (std::size_t base = 0; base < n; base += inner) {
      std::size_t o = 0;
      for (std::size_t d = 0; d + 1 < rank; ++d) o += runs[d][runIndex[d]].outPos[m[d]] * outStride[d];
      if (rank == 0) {
        out[0] = decode(static_cast<double>(raw[0]));
      } else {
        for (std::size_t i = 0; i < inner; ++i) out[o + (*innerPos)[i]] = decode(static_cast<double>(raw[base + i]));
      }
      for (std::size_t d = rank >= 2 ? rank - 1 : 0; d-- > 0;) {
        if (++m[d] < count[d]) break;
        m[d] = 0;
      }
    }
    // Next combination of runs.
    std::size_t d = rank;
    while (d-- > 0) {
      if (++runIndex[d] < runs[d].size()) break;
      runIndex[d] = 0;
    }
    if (d == static_cast<std::size_t>(-1)) break;
  }
  return Ok{};
}

}  // namespace

template <class Out>
Result<std::vector<Out>> readPicked(const io::NetcdfFile& f, const io::NcVar& v, const Picks& picks) {
  if (picks.size() != v.shape.size())
    return makeError(f.message("variable '" + v.name + "': internal error, " + std::to_string(picks.size()) +
                               " index lists for " + std::to_string(v.shape.size()) + " dimensions"));
  if (!io::ncTypeIsNumeric(v.type)) return makeError(f.message("variable '" + v.name + "' is not numeric"));
  std::size_t n = 1;
  std::vector<std::size_t> shape(picks.size());
  for (std::size_t d = 0; d < picks.size(); ++d) {
    shape[d] = picks[d].size();
    for (std::size_t i : picks[d])
      if (i >= v.shape[d])
        return makeError(f.message("variable '" + v.name + "': index " + std::to_string(i) + " outside dimension " +
                                   std::to_string(d) + " of length " + std::to_string(v.shape[d])));
    if (shape[d] != 0 && n > io::kMaxElementsPerRead / shape[d])
      return makeError(f.message("variable '" + v.name + "': the region asked for holds more than " +
                                 std::to_string(io::kMaxElementsPerRead) + " values; read a smaller crop"));
    n *= shape[d];
  }
  if (auto st = f.checkReadable(v, n, io::ncTypeSize(v.type)); !st) return st.forwardError();
  auto packing = packingOf(f, v);
  if (!packing) return packing.forwardError();
  std::vector<Out> out(n);
  if (n == 0) return out;
  std::vector<std::vector<Run>> runs(picks.size());
  for (std::size_t d = 0; d < picks.size(); ++d) runs[d] = runsOf(picks[d]);
  Status st = io::visitNumericType(v.type, [&](auto tag) -> Status {
    using T = decltype(tag);
    return readRuns<Out, T>(f, v, runs, shape, *packing, out);
  });
  if (!st) return st.forwardError();
  return out;
}

template Result<std::vector<float>> readPicked<float>(const io::NetcdfFile&, const io::NcVar&, const Picks&);
template Result<std::vector<double>> readPicked<double>(const io::NetcdfFile&, const io::NcVar&, const Picks&);

template <class T>
void averageAdjacent(std::vector<T>& a, std::vector<std::size_t>& shape, std::size_t axis) {
  std::size_t outer = 1, inner = 1;
  for (std::size_t d = 0; d < axis; ++d) outer *= shape[d];
  for (std::size_t d = axis + 1; d < shape.size(); ++d) inner *= shape[d];
  const std::size_t len = shape[axis];
  if (len < 2) return;
  std::vector<T> out(outer * (len - 1) * inner);
  for (std::size_t o = 0; o < outer; ++o)
    for (std::size_t k = 0; k + 1 < len; ++k) {
      const T* lo = a.data() + (o * len + k) * inner;
      const T* hi = lo + inner;
      T* dst = out.data() + (o * (len - 1) + k) * inner;
      for (std::size_t i = 0; i < inner; ++i)
        dst[i] = static_cast<T>(0.5 * (static_cast<double>(lo[i]) + static_cast<double>(hi[i])));
    }
  a.swap(out);
  shape[axis] = len - 1;
}

template void averageAdjacent<float>(std::vector<float>&, std::vector<std::size_t>&, std::size_t);
template void averageAdjacent<double>(std::vector<double>&, std::vector<std::size_t>&, std::size_t);

}  // namespace atmoglobe::volume::grid
