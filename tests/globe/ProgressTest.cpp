// globe/Progress.h: the formatter and the plain-lines form used in logs (no terminal).
#include <atmoglobe/globe/Progress.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

using namespace atmoglobe::globe;

namespace {

// A progress writing into memory, with a clock the test moves.
struct Captured {
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* stream = open_memstream(&buffer, &size);
  double seconds = 0.0;
  ~Captured() {
    if (stream) std::fclose(stream);
    std::free(buffer);
  }
  Progress::Options options(ProgressStyle style) {
    Progress::Options o;
    o.style = style;
    o.stream = stream;
    o.clock = [this] { return seconds; };
    o.widthChars = 80;
    return o;
  }
  std::string text() {
    std::fflush(stream);
    return std::string(buffer, size);
  }
  std::vector<std::string> lines() {
    std::vector<std::string> out;
    std::istringstream in(text());
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
  }
};

}  // namespace

TEST(Progress, DurationsReadAsClockTimes) {
  EXPECT_EQ(formatDuration(0.0), "0:00");
  EXPECT_EQ(formatDuration(7.4), "0:07");
  EXPECT_EQ(formatDuration(59.6), "1:00");  // rounded to the second
  EXPECT_EQ(formatDuration(754.0), "12:34");
  EXPECT_EQ(formatDuration(3723.0), "1:02:03");
  EXPECT_EQ(formatDuration(-1.0), "--:--");
  EXPECT_EQ(formatDuration(std::nan("")), "--:--");
}

TEST(Progress, EtaFollowsTheRateSoFar) {
  // 7 of 20 in 14 s: 2 s each, 13 left -> 26 s.
  EXPECT_DOUBLE_EQ(estimateRemainingSeconds({"x", 7, 20, 14.0, ""}), 26.0);
  EXPECT_LT(estimateRemainingSeconds({"x", 0, 20, 3.0, ""}), 0.0);  // nothing done: unknown
  EXPECT_LT(estimateRemainingSeconds({"x", 5, 0, 3.0, ""}), 0.0);   // no total: unknown
  EXPECT_EQ(estimateRemainingSeconds({"x", 20, 20, 3.0, ""}), 0.0);
}

TEST(Progress, BarShowsFractionCountElapsedAndEta) {
  const std::string bar = formatProgressBar({"tiles", 5, 20, 10.0, "3/1/2.png"}, 100);
  // 5/20 = 25 %: a quarter of the cells filled.
  EXPECT_NE(bar.find("tiles ["), std::string::npos) << bar;
  EXPECT_NE(bar.find(" 25%"), std::string::npos) << bar;
  EXPECT_NE(bar.find("5/20"), std::string::npos) << bar;
  EXPECT_NE(bar.find("0:10 elapsed"), std::string::npos) << bar;
  EXPECT_NE(bar.find("ETA 0:30"), std::string::npos) << bar;  // 2 s each, 15 left
  EXPECT_NE(bar.find("3/1/2.png"), std::string::npos) << bar;
  const std::size_t open = bar.find('['), close = bar.find(']');
  const std::string cells = bar.substr(open + 1, close - open - 1);
  const auto filled = static_cast<std::size_t>(std::count(cells.begin(), cells.end(), '#'));
  EXPECT_EQ(filled, cells.size() / 4) << bar;
  EXPECT_EQ(bar.find('\r'), std::string::npos);
  EXPECT_EQ(bar.find('\n'), std::string::npos);
  // It fits the terminal: a long item is cut, never the line wrapped.
  const std::string narrow = formatProgressBar({"tiles", 5, 20, 10.0, std::string(200, 'x')}, 60);
  EXPECT_LE(narrow.size(), 60u) << narrow;
}

TEST(Progress, LineFormHasNoBar) {
  EXPECT_EQ(formatProgressLine({"loading", 2, 3, 4.0, "KTLX.nc"}),
            "loading: 66% (2/3), 0:04 elapsed, ETA 0:02: KTLX.nc");
  EXPECT_EQ(formatProgressLine({"frames", 3, 0, 1.0, ""}), "frames: 3, 0:01 elapsed");
}

TEST(Progress, LogsGetOneLinePerTenthAndNoCarriageReturns) {
  Captured c;
  {
    Progress p("tiles", 1000, c.options(ProgressStyle::Lines));
    for (int i = 0; i < 1000; ++i) {
      c.seconds += 0.01;
      p.advance();
    }
  }
  const std::string text = c.text();
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_EQ(text.find("\x1b"), std::string::npos);
  const auto lines = c.lines();
  // 10 %, 20 %, ... 90 %, then the done line: 10 lines for 1000 steps.
  ASSERT_EQ(lines.size(), 10u) << text;
  EXPECT_EQ(lines[0], "tiles: 10% (100/1000), 0:01 elapsed, ETA 0:09");
  EXPECT_EQ(lines[8].rfind("tiles: 90% (900/1000)", 0), 0u) << lines[8];
  EXPECT_EQ(lines[9], "tiles: done, 1000/1000 in 0:10");
}

TEST(Progress, FewItemsGetOneLineEach) {
  Captured c;
  Progress p("loading", 3, c.options(ProgressStyle::Lines));
  for (const char* f : {"a.nc", "b.nc", "c.nc"}) {
    c.seconds += 1.0;
    p.advance(1, f);
  }
  p.finish();
  const auto lines = c.lines();
  ASSERT_EQ(lines.size(), 4u) << c.text();
  EXPECT_EQ(lines[0], "loading: 33% (1/3), 0:01 elapsed, ETA 0:02: a.nc");
  EXPECT_EQ(lines[2], "loading: 100% (3/3), 0:03 elapsed: c.nc");
  EXPECT_EQ(lines[3], "loading: done, 3/3 in 0:03");
}

TEST(Progress, AnEarlyEndSaysWhereItStopped) {
  Captured c;
  {
    Progress p("frames", 4, c.options(ProgressStyle::Lines));
    p.advance();
  }  // destroyed after 1 of 4 (an error return)
  const auto lines = c.lines();
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.back(), "frames: stopped at 1/4 in 0:00");
}

TEST(Progress, QuietWritesNothing) {
  Captured c;
  {
    Progress p("tiles", 10, c.options(ProgressStyle::Quiet));
    p.advance(5);
    p.finish();
  }
  EXPECT_EQ(c.text(), "");
  // The process-wide default (--quiet) applies to Auto.
  setDefaultProgressStyle(ProgressStyle::Quiet);
  {
    Progress p("tiles", 10, c.options(ProgressStyle::Auto));
    EXPECT_EQ(p.style(), ProgressStyle::Quiet);
    p.advance(10);
  }
  setDefaultProgressStyle(ProgressStyle::Auto);
  EXPECT_EQ(c.text(), "");
}

TEST(Progress, AutoIsLinesWhenTheStreamIsNotATerminal) {
  Captured c;  // a memory stream is not a terminal
  Progress p("x", 2, c.options(ProgressStyle::Auto));
  EXPECT_EQ(p.style(), ProgressStyle::Lines);
}

TEST(Progress, BarRedrawsOneLineInPlace) {
  Captured c;
  Progress p("tiles", 4, c.options(ProgressStyle::Bar));
  for (int i = 0; i < 4; ++i) {
    c.seconds += 1.0;  // past the 0.1 s redraw limit each time
    p.advance();
  }
  p.finish();
  const std::string text = c.text();
  // Four redraws and the last line, each starting with a carriage return; one newline, at the end.
  EXPECT_EQ(static_cast<int>(std::count(text.begin(), text.end(), '\r')), 5) << text;
  EXPECT_EQ(static_cast<int>(std::count(text.begin(), text.end(), '\n')), 1) << text;
  EXPECT_NE(text.find("tiles: done, 4/4 in 0:04"), std::string::npos) << text;
}

TEST(Progress, EtaIsUnknownInTheFirstQuarterSecond) {
  EXPECT_LT(estimateRemainingSeconds({"x", 1, 170, 0.01, ""}), 0.0);  // not "ETA 0:00" from one quick tile
  EXPECT_EQ(formatProgressLine({"x", 1, 170, 0.01, ""}), "x: 0% (1/170), 0:00 elapsed, ETA --:--");
}

TEST(Progress, MessagesPrintAboveTheBar) {
  Captured c;
  Progress p("loading", 3, c.options(ProgressStyle::Bar));
  c.seconds = 1.0;
  p.advance(1, "a.nc");
  p.print("a.nc: antenna height ...");
  const std::string text = c.text();
  // The bar's line is cleared, the message ends with its own newline, and the bar is drawn again.
  const std::size_t message = text.find("\r\x1b[Ka.nc: antenna height ...\n");
  ASSERT_NE(message, std::string::npos) << text;
  EXPECT_NE(text.find("\rloading [", message), std::string::npos) << text;
}

TEST(Progress, MessagesInLogsArePlainLines) {
  Captured c;
  Progress p("loading", 3, c.options(ProgressStyle::Lines));
  p.print("hello");
  EXPECT_EQ(c.text(), "hello\n");
}
