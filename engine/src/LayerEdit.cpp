// Layer edits of the viewer's control panel (LayerEdit.h).
#include <atmoglobe/engine/LayerEdit.h>

#include <algorithm>
#include <cstdio>

namespace atmoglobe::engine {

const std::vector<std::string>& colorTableChoices() {
  static const std::vector<std::string> choices{"auto",    "NWS",   "velocity",  "cividis",
                                                "viridis", "turbo", "grayscale", "greens"};
  return choices;
}

std::vector<std::size_t> moveInOrder(std::vector<std::size_t> order, std::size_t position, int delta) {
  if (position >= order.size()) return order;
  const auto last = static_cast<long>(order.size()) - 1;
  const auto to = static_cast<std::size_t>(std::clamp(static_cast<long>(position) + delta, 0L, last));
  const std::size_t moved = order[position];
  order.erase(order.begin() + static_cast<std::ptrdiff_t>(position));
  order.insert(order.begin() + static_cast<std::ptrdiff_t>(to), moved);
  return order;
}

std::string formatBytes(std::uint64_t bytes) {
  char text[32];
  const double b = static_cast<double>(bytes);
  if (bytes < 1024) {
    std::snprintf(text, sizeof text, "%llu B", static_cast<unsigned long long>(bytes));
  } else if (b < 1024.0 * 1024.0) {
    std::snprintf(text, sizeof text, "%.1f KiB", b / 1024.0);
  } else if (b < 1024.0 * 1024.0 * 1024.0) {
    std::snprintf(text, sizeof text, "%.1f MiB", b / (1024.0 * 1024.0));
  } else {
    std::snprintf(text, sizeof text, "%.2f GiB", b / (1024.0 * 1024.0 * 1024.0));
  }
  return text;
}

}  // namespace atmoglobe::engine
