// Statistics over the members of an ensemble (GridReader.h, EnsembleStatistic; docs/grids.md,
// "Ensembles"): every member read in turn with readGridVolume, reduced value by value in double.
#include "GridInternal.h"

#include <atmoglobe/globe/Text.h>
#include <atmoglobe/volume/GridReader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

namespace atmoglobe::volume {

namespace {
constexpr const char* kForms = "mean, spread, min, max or prob:OPVALUE (OP one of >=, >, <=, <; e.g. prob:>=273.15)";

bool passes(double v, const EnsembleStatistic& s) {
  if (s.comparison == ">=") return v >= s.threshold;
  if (s.comparison == ">") return v > s.threshold;
  if (s.comparison == "<=") return v <= s.threshold;
  return v < s.threshold;
}
}  // namespace

Result<EnsembleStatistic> parseEnsembleStatistic(const std::string& text) {
  EnsembleStatistic s;
  if (text == "mean") return s;
  if (text == "spread") {
    s.kind = EnsembleStatistic::Kind::Spread;
    return s;
  }
  if (text == "min") {
    s.kind = EnsembleStatistic::Kind::Minimum;
    return s;
  }
  if (text == "max") {
    s.kind = EnsembleStatistic::Kind::Maximum;
    return s;
  }
  if (text.rfind("prob:", 0) == 0) {
    std::string rest = text.substr(5);
    // std::string operators (assigning a const char* here trips GCC 12's -Wrestrict falsely).
    static const std::string kOperators[] = {">=", "<=", ">", "<"};
    for (const std::string& op : kOperators) {
      if (rest.rfind(op, 0) != 0) continue;
      const std::string number = rest.substr(op.size());
      double v = 0.0;
      const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), v);
      if (number.empty() || ec != std::errc() || end != number.data() + number.size() || !std::isfinite(v))
        return makeError("ensemble statistic '" + text + "': '" + number + "' is not a finite number; expected " +
                         kForms);
      s.kind = EnsembleStatistic::Kind::Probability;
      s.comparison = op;
      s.threshold = v;
      return s;
    }
  }
  return makeError("ensemble statistic '" + text + "': expected " + kForms);
}

std::string toString(const EnsembleStatistic& s) {
  switch (s.kind) {
    case EnsembleStatistic::Kind::Mean: return "mean";
    case EnsembleStatistic::Kind::Spread: return "spread";
    case EnsembleStatistic::Kind::Minimum: return "min";
    case EnsembleStatistic::Kind::Maximum: return "max";
    case EnsembleStatistic::Kind::Probability: return "prob:" + s.comparison + numberText(s.threshold);
  }
  return "mean";
}

namespace {

// The reads of every member of `one`'s variable (netCDF: an index along the ensemble dimension of
// `extraDimensions`; GRIB: each `number` the file has); `what` names the caller in messages.
Result<std::vector<GridReadOptions>> memberReads(const std::string& path, const GridReadOptions& one,
                                                 const std::vector<GridExtraDimension>& extraDimensions,
                                                 const std::string& variable, const std::string& what) {
  std::vector<GridReadOptions> reads;
  const auto dimension = std::find_if(extraDimensions.begin(), extraDimensions.end(),
                                      [](const GridExtraDimension& d) { return d.ensemble; });
  if (dimension != extraDimensions.end()) {
    if (one.extraIndex.count(dimension->name))
      return makeError(path + ": " + what + " combines every member; index " +
                       std::to_string(one.extraIndex.at(dimension->name)) + " along '" + dimension->name +
                       "' asked for too: give one or the other");
    for (std::size_t i = 0; i < dimension->length; ++i) {
      GridReadOptions r = one;
      r.extraIndex[dimension->name] = i;
      reads.push_back(std::move(r));
    }
  } else {
    auto info = describeGridFile(path, one);
    if (!info) return info.forwardError();
    for (long m : info->members) {
      if (m < 0) continue;
      GridReadOptions r = one;
      r.member = m;
      reads.push_back(std::move(r));
    }
  }
  if (reads.size() < 2)
    return makeError(path + ": '" + variable + "' has no ensemble members to combine (" + what +
                     " needs two or more: an ensemble dimension such as number or realization, or GRIB messages "
                     "with several `number`s)");
  return reads;
}

}  // namespace

Result<std::vector<EnsembleMemberSelection>> ensembleMemberSelections(const std::string& path,
                                                                      const GridReadOptions& read) {
  GridReadOptions one = read;
  one.ensemble.reset();
  one.member = -1;
  auto info = describeGridFile(path, one);
  if (!info) return info.forwardError();
  auto reads = memberReads(path, one, info->extraDimensions, info->variable, "drawing every member");
  if (!reads) return reads.forwardError();
  std::vector<EnsembleMemberSelection> out;
  for (const GridReadOptions& r : *reads) out.push_back({r.member, r.extraIndex});
  return out;
}

namespace grid {

Result<GridVolume> readGridEnsembleStatistic(const std::string& path, const GridReadOptions& options) {
  const EnsembleStatistic stat = *options.ensemble;
  GridReadOptions one = options;
  one.ensemble.reset();
  if (options.member >= 0)
    return makeError(path + ": an ensemble statistic (" + toString(stat) + ") combines every member; member " +
                     std::to_string(options.member) + " asked for too: give one or the other");
  // The first member fixes the grid, the heights and which dimension holds the members.
  auto first = readGridVolume(path, one);
  if (!first) return first.forwardError();
  const auto dimension = std::find_if(first->extraDimensions.begin(), first->extraDimensions.end(),
                                      [](const GridExtraDimension& d) { return d.ensemble; });
  auto reads =
      memberReads(path, one, first->extraDimensions, first->variable, "an ensemble statistic (" + toString(stat) + ")");
  if (!reads) return reads.forwardError();

  const std::size_t n = first->values.size();
  std::vector<double> sum(n, 0.0), sumSquares(stat.kind == EnsembleStatistic::Kind::Spread ? n : 0, 0.0);
  std::vector<float> extreme;
  std::vector<unsigned> count;
  if (stat.kind == EnsembleStatistic::Kind::Minimum || stat.kind == EnsembleStatistic::Kind::Maximum)
    extreme.assign(n, std::numeric_limits<float>::quiet_NaN());
  if (stat.kind == EnsembleStatistic::Kind::Probability) count.assign(n, 0);
  std::vector<bool> missing(n, false);
  std::uint64_t bytesRead = 0;
  std::vector<long> members;
  // Mean and spread in two passes would read every member twice; one pass with double sums of x
  // and x^2 loses nothing that matters for float output: x^2 of 1e5-scale values keeps 11
  // significant digits after the subtraction for a spread 1e-3 of the mean.
  const bool netcdfMembers = dimension != first->extraDimensions.end();
  for (std::size_t m = 0; m < reads->size(); ++m) {
    // The first member's read is the one above (index 0, or the first `number`): not read twice.
    std::optional<GridVolume> other;
    if (m > 0) {
      auto read = readGridVolume(path, (*reads)[m]);
      if (!read) return read.forwardError();
      if (read->nx != first->nx || read->ny != first->ny || read->nz != first->nz || read->values.size() != n)
        return makeError(path + ": ensemble member " + std::to_string(m) + " of '" + read->variable +
                         "' has another shape than the first");
      other = std::move(*read);
    }
    const GridVolume& g = m == 0 ? *first : *other;
    bytesRead += g.bytesRead;
    if (netcdfMembers) {
      // The ensemble coordinate's value, or the index where the dimension has none.
      const auto d = std::find_if(g.extraDimensions.begin(), g.extraDimensions.end(),
                                  [](const GridExtraDimension& e) { return e.ensemble; });
      members.push_back(d != g.extraDimensions.end() && std::isfinite(d->value) ? std::lround(d->value)
                                                                                : static_cast<long>(m));
    } else {
      members.push_back(g.member);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const float v = g.values[i];
      if (!std::isfinite(v)) {
        missing[i] = true;
        continue;
      }
      const double x = v;
      switch (stat.kind) {
        case EnsembleStatistic::Kind::Mean: sum[i] += x; break;
        case EnsembleStatistic::Kind::Spread:
          sum[i] += x;
          sumSquares[i] += x * x;
          break;
        case EnsembleStatistic::Kind::Minimum:
          if (!(extreme[i] <= v)) extreme[i] = v;
          break;
        case EnsembleStatistic::Kind::Maximum:
          if (!(extreme[i] >= v)) extreme[i] = v;
          break;
        case EnsembleStatistic::Kind::Probability: count[i] += passes(x, stat); break;
      }
    }
  }
  GridVolume out = std::move(*first);
  const double members_ = static_cast<double>(reads->size());
  out.valueMin = std::numeric_limits<float>::quiet_NaN();
  out.valueMax = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < n; ++i) {
    float v = std::numeric_limits<float>::quiet_NaN();
    if (!missing[i]) {
      switch (stat.kind) {
        case EnsembleStatistic::Kind::Mean: v = static_cast<float>(sum[i] / members_); break;
        case EnsembleStatistic::Kind::Spread: {
          const double mean = sum[i] / members_;
          v = static_cast<float>(std::sqrt(std::max(0.0, sumSquares[i] / members_ - mean * mean)));
          break;
        }
        case EnsembleStatistic::Kind::Minimum:
        case EnsembleStatistic::Kind::Maximum: v = extreme[i]; break;
        case EnsembleStatistic::Kind::Probability:
          v = static_cast<float>(100.0 * static_cast<double>(count[i]) / members_);
          break;
      }
    }
    out.values[i] = v;
    if (std::isfinite(v)) {
      if (!(out.valueMin <= v)) out.valueMin = v;
      if (!(out.valueMax >= v)) out.valueMax = v;
    }
  }
  out.member = -1;
  out.bytesRead = bytesRead;
  out.ensembleStatistic = toString(stat);
  out.ensembleMembers = std::move(members);
  if (stat.kind == EnsembleStatistic::Kind::Probability) {
    out.longName = "probability of " + (out.longName.empty() ? out.variable : out.longName) + " " + stat.comparison +
                   " " + numberText(stat.threshold) + (out.units.empty() ? "" : " " + out.units);
    out.units = "%";
    out.standardName.clear();
  }
  out.heightNote += std::string(out.heightNote.empty() ? "" : "; ") + "heights of the first member";
  return out;
}

}  // namespace grid
}  // namespace atmoglobe::volume
