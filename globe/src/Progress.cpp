#include <atmoglobe/globe/Progress.h>

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace atmoglobe::globe {

namespace {
std::atomic<ProgressStyle> gDefaultStyle{ProgressStyle::Auto};

double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::size_t terminalWidth(std::FILE* stream) {
  winsize ws{};
  if (ioctl(fileno(stream), TIOCGWINSZ, &ws) == 0 && ws.ws_col >= 20) return ws.ws_col;
  return 80;
}

std::string percentText(const ProgressState& s) {
  const double f = static_cast<double>(std::min(s.done, s.total)) / static_cast<double>(s.total);
  char b[16];
  std::snprintf(b, sizeof b, "%3d%%", static_cast<int>(std::floor(f * 100.0)));
  return b;
}
}  // namespace

void setDefaultProgressStyle(ProgressStyle style) { gDefaultStyle = style; }
ProgressStyle defaultProgressStyle() { return gDefaultStyle; }

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0 || seconds > 3.6e8) return "--:--";
  const long long t = static_cast<long long>(std::llround(seconds));
  char b[32];
  if (t >= 3600) std::snprintf(b, sizeof b, "%lld:%02lld:%02lld", t / 3600, (t / 60) % 60, t % 60);
  else std::snprintf(b, sizeof b, "%lld:%02lld", t / 60, t % 60);
  return b;
}

double estimateRemainingSeconds(const ProgressState& s) {
  // Unknown before anything is done or in the first quarter second (too little to go by).
  if (s.total == 0 || s.done == 0 || !(s.elapsedSeconds >= 0.25)) return -1.0;
  if (s.done >= s.total) return 0.0;
  return s.elapsedSeconds / static_cast<double>(s.done) * static_cast<double>(s.total - s.done);
}

std::string formatProgressBar(const ProgressState& s, std::size_t widthChars) {
  std::string tail;
  if (s.total > 0) tail.append("  ").append(percentText(s));
  tail.append("  ").append(std::to_string(s.done));
  if (s.total > 0) tail.append("/").append(std::to_string(s.total));
  tail.append("  ").append(formatDuration(s.elapsedSeconds)).append(" elapsed");
  if (s.total > 0) tail.append("  ETA ").append(formatDuration(estimateRemainingSeconds(s)));
  // The bar takes what is left, between 10 and 20 cells; the item what remains after it.
  const std::size_t fixed = s.label.size() + 3 + tail.size();
  const std::size_t cells = widthChars > fixed + 10 ? std::min<std::size_t>(20, widthChars - fixed) : 10;
  std::string bar = s.label + " [";
  if (s.total > 0) {
    const std::size_t filled = std::min(s.done, s.total) * cells / s.total;
    bar.append(filled, '#').append(cells - filled, '.');
  } else {
    bar.append(cells, '.');
  }
  bar.append("]").append(tail);
  if (!s.item.empty() && bar.size() + 12 <= widthChars) {  // an item cut to under 10 characters says nothing
    std::string item = s.item;
    const std::size_t room = widthChars - bar.size() - 2;
    if (item.size() > room) item = std::string("...").append(item.substr(item.size() - (room > 3 ? room - 3 : 0)));
    bar.append("  ").append(item);
  }
  if (bar.size() > widthChars) bar.resize(widthChars);
  return bar;
}

std::string formatProgressLine(const ProgressState& s) {
  std::string line = s.label + ": ";
  if (s.total > 0) {
    std::string pct = percentText(s);
    pct.erase(0, pct.find_first_not_of(' '));
    line.append(pct)
        .append(" (")
        .append(std::to_string(s.done))
        .append("/")
        .append(std::to_string(s.total))
        .append(")");
  } else {
    line += std::to_string(s.done);
  }
  line.append(", ").append(formatDuration(s.elapsedSeconds)).append(" elapsed");
  if (s.total > 0 && s.done < s.total) line.append(", ETA ").append(formatDuration(estimateRemainingSeconds(s)));
  if (!s.item.empty()) line.append(": ").append(s.item);
  return line;
}

Progress::Progress(std::string label, std::size_t total) : Progress(std::move(label), total, Options{}) {}

Progress::Progress(std::string label, std::size_t total, Options options)
    : label_(std::move(label)), total_(total), options_(std::move(options)) {
  style_ = options_.style == ProgressStyle::Auto ? defaultProgressStyle() : options_.style;
  if (!options_.stream) style_ = ProgressStyle::Quiet;
  if (style_ == ProgressStyle::Auto)
    style_ = isatty(fileno(options_.stream)) ? ProgressStyle::Bar : ProgressStyle::Lines;
  if (style_ == ProgressStyle::Bar && options_.widthChars == 0) options_.widthChars = terminalWidth(options_.stream);
  start_ = now();
}

Progress::~Progress() { finish(total_ > 0 && done_ < total_); }

double Progress::now() const { return options_.clock ? options_.clock() : steadySeconds(); }

void Progress::advance(std::size_t count, std::string_view item) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  done_ += count;
  item_ = std::string(item);
  reportLocked(false);
}

void Progress::update(std::size_t done, std::string_view item) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  done_ = std::max(done_, done);  // reports from worker threads may arrive out of order
  item_ = std::string(item);
  reportLocked(false);
}

void Progress::print(std::string_view line, std::FILE* out) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!out) out = options_.stream ? options_.stream : stderr;
  if (style_ == ProgressStyle::Bar && drewBar_ && !finished_) {
    std::fputs("\r\x1b[K", options_.stream);  // the bar's line cleared, the line printed, the bar below it
    std::fflush(options_.stream);
    std::fprintf(out, "%.*s\n", static_cast<int>(line.size()), line.data());
    std::fflush(out);
    lastDraw_ = -1.0;
    reportLocked(true);
  } else {
    std::fprintf(out, "%.*s\n", static_cast<int>(line.size()), line.data());
    std::fflush(out);
  }
}

void Progress::reportLocked(bool force) {
  if (style_ == ProgressStyle::Quiet) return;
  const double t = now();
  const ProgressState state{label_, done_, total_, t - start_, item_};
  if (style_ == ProgressStyle::Bar) {
    if (force && lastDraw_ < 0.0 && done_ == 0) return;  // nothing to redraw yet
    if (!force && lastDraw_ >= 0.0 && t - lastDraw_ < 0.1) return;
    lastDraw_ = t;
    const std::string bar = formatProgressBar(state, options_.widthChars);
    std::fprintf(options_.stream, "\r%s\x1b[K", bar.c_str());
    std::fflush(options_.stream);
    drewBar_ = true;
    return;
  }
  // Lines: every item when there are 10 or fewer, else each time another tenth is done.
  bool print = force;
  if (!print && total_ > 0 && total_ <= 10) print = true;
  if (!print && total_ > 10) {
    const long tenth = static_cast<long>(std::min(done_, total_) * 10 / total_);
    if (tenth > lastTenth_) {
      lastTenth_ = tenth;
      print = tenth < 10;  // the last tenth is the "done" line of finish()
    }
  }
  if (!print && total_ == 0 && done_ > 0 && (done_ & (done_ - 1)) == 0) print = true;  // 1, 2, 4, 8, ...
  if (!print) return;
  std::fprintf(options_.stream, "%s\n", formatProgressLine(state).c_str());
  std::fflush(options_.stream);
}

void Progress::finish(bool failed) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  finished_ = true;
  if (style_ == ProgressStyle::Quiet) return;
  const double elapsed = now() - start_;
  std::string count = std::to_string(done_);
  if (total_ > 0) count.append("/").append(std::to_string(total_));
  const std::string last = label_ + (failed ? ": stopped at " : ": done, ") + count + " in " + formatDuration(elapsed);
  if (style_ == ProgressStyle::Bar) {
    std::fprintf(options_.stream, "\r%s\x1b[K\n", last.c_str());
  } else {
    std::fprintf(options_.stream, "%s\n", last.c_str());
  }
  std::fflush(options_.stream);
}

}  // namespace atmoglobe::globe
