#pragma once
// Progress of the steps that can take more than a second (tile pyramid builds, loading several
// volumes, the bench, time-series renders, NRRD conversion), on stderr:
//  - on a terminal (isatty): one line redrawn in place (at most 10 times a second):
//      tiles [##########..........]  50%  2730/5460  0:12 elapsed  ETA 0:12
//  - otherwise (logs, CI, pipes): plain lines, never a carriage return: one each time another
//    tenth is done, or one per item when there are 10 items or fewer, and a last line:
//      tiles: 50% (2730/5460), 0:12 elapsed, ETA 0:12
//      tiles: done, 5460/5460 in 0:24
//  - quiet (`--quiet`): nothing.
// GL-free and thread-safe (advance() may be called from worker threads).
#include <cstddef>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>

namespace atmoglobe::globe {

enum class ProgressStyle {
  Auto,   ///< Bar on a terminal, Lines otherwise
  Bar,    ///< a line redrawn in place
  Lines,  ///< plain lines (logs)
  Quiet,  ///< nothing
};

/// The process-wide style of new Progress objects that ask for Auto (the tools' `--quiet` sets
/// Quiet). Default: Auto.
void setDefaultProgressStyle(ProgressStyle style);
ProgressStyle defaultProgressStyle();

/// What a progress line shows.
struct ProgressState {
  std::string label;
  std::size_t done = 0;
  std::size_t total = 0;        ///< 0: unknown (no fraction, no ETA)
  double elapsedSeconds = 0.0;  ///< since the start
  std::string item;             ///< the item just finished (may be empty)
};

/// "0:07", "12:34", "1:02:03"; "--:--" for a negative or non-finite value.
std::string formatDuration(double seconds);
/// Seconds left, from the rate so far (done / elapsed); negative when unknown (nothing done yet,
/// or no total).
double estimateRemainingSeconds(const ProgressState& state);
/// The terminal form: "LABEL [####......]  35%  7/20  0:04 elapsed  ETA 0:07  ITEM", at most
/// `widthChars` characters (the bar shrinks first, then the item is cut).
std::string formatProgressBar(const ProgressState& state, std::size_t widthChars = 80);
/// The log form: "LABEL: 35% (7/20), 0:04 elapsed, ETA 0:07: ITEM".
std::string formatProgressLine(const ProgressState& state);

class Progress {
 public:
  struct Options {
    ProgressStyle style = ProgressStyle::Auto;
    std::FILE* stream = stderr;
    /// Seconds since an arbitrary start (tests inject one); default: the steady clock.
    std::function<double()> clock;
    /// Terminal width for the bar; 0: asked from the terminal (80 when it cannot say).
    std::size_t widthChars = 0;
  };

  Progress(std::string label, std::size_t total);
  Progress(std::string label, std::size_t total, Options options);
  /// finish() if not done yet (as failed when fewer than the total were done: an early return).
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// `count` more done; `item` names the last one (a file, a frame).
  void advance(std::size_t count = 1, std::string_view item = {});
  /// A message line that must not be mixed into the bar: on a terminal the bar is cleared, the
  /// line printed and the bar drawn again below it; otherwise (and when quiet) just the line.
  /// `out`: where the line goes (default: the progress stream), e.g. stdout for a result line.
  void print(std::string_view line, std::FILE* out = nullptr);
  /// Sets the count done (a callback that reports totals, e.g. buildPyramid's).
  void update(std::size_t done, std::string_view item = {});
  /// The last line ("LABEL: done, N/N in 0:12"); with failed = true, "LABEL: stopped at ...".
  void finish(bool failed = false);

  ProgressStyle style() const { return style_; }

 private:
  void reportLocked(bool force);
  double now() const;

  std::mutex mutex_;
  std::string label_;
  std::size_t total_;
  Options options_;
  ProgressStyle style_;
  double start_ = 0.0;
  std::size_t done_ = 0;
  std::string item_;
  long lastTenth_ = 0;
  double lastDraw_ = -1.0;
  bool finished_ = false;
  bool drewBar_ = false;
};

}  // namespace atmoglobe::globe
