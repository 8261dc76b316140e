// The viewer's script format (engine/ViewerScript.h), parsed without a window.
#include <atmoglobe/engine/ViewerScript.h>

#include <gtest/gtest.h>

using namespace atmoglobe;
using engine::ScriptAction;

TEST(ViewerScript, ParsesEveryAction) {
  const auto s = engine::parseViewerScript(
      "# a comment\n\ncamera 35 -97 3e5 0 -90\nmove 10 20\ndown right shift\nup right\nclick 5 6\n"
      "drag 1 2 3 4 12 shift\nwheel 100 100 -2\nkey pageup\nkey Right ctrl\ntype New York\nwait 3\n"
      "flyto  Oklahoma City \nreadout\nscreenshot out dir/a.png\r\n",
      "t.txt");
  ASSERT_TRUE(s) << s.error();
  ASSERT_EQ(s->size(), 14u);
  const auto& a = *s;
  EXPECT_EQ(a[0].kind, ScriptAction::Kind::Camera);
  EXPECT_EQ(a[0].line, 3);
  EXPECT_EQ(a[0].numbers, (std::vector<double>{35, -97, 3e5, 0, -90}));
  EXPECT_EQ(a[2].kind, ScriptAction::Kind::Down);
  EXPECT_EQ(a[2].button, 1);
  EXPECT_TRUE(a[2].shift);
  EXPECT_EQ(a[5].numbers.size(), 5u);
  EXPECT_TRUE(a[5].shift);
  EXPECT_EQ(a[6].numbers[2], -2.0);
  EXPECT_EQ(a[7].text, "PageUp");  // key names are case-insensitive, given back canonical
  EXPECT_TRUE(a[8].ctrl);
  EXPECT_EQ(a[9].text, "New York");
  EXPECT_EQ(a[11].text, "Oklahoma City");
  EXPECT_EQ(a[13].text, "out dir/a.png");
  EXPECT_EQ(a[13].line, 16);
}

TEST(ViewerScript, ErrorsNameTheLineAndTheProblem) {
  const struct {
    const char* text;
    const char* expect;
  } bad[] = {
      {"move 1 2\njump 3\n", "s.txt line 2: unknown action 'jump'"},
      {"drag 1 2 3\n", "s.txt line 1: drag: expected drag X0 Y0 X1 Y1"},
      {"\n\nkey F13\n", "s.txt line 3: key: unknown key 'F13'"},
      {"wait 0\n", "line 1: wait: FRAMES must be a whole number"},
      {"wait 2.5\n", "line 1: wait: FRAMES"},
      {"move 1 nan\n", "line 1: move: expected move X Y"},
      {"click 1 2 sideways\n", "unexpected 'sideways'"},
      {"screenshot a.jpg\n", "line 1: screenshot: the file must end in .png"},
      {"flyto\n", "line 1: flyto: expected flyto NAME"},
      {"camera 95 0 1000\n", "line 1: camera: latitude in [-90, 90]"},
      {"camera 10 0 0\n", "height in [1, 1e8]"},
  };
  for (const auto& b : bad) {
    const auto s = engine::parseViewerScript(b.text, "s.txt");
    ASSERT_FALSE(s) << b.text;
    EXPECT_NE(s.error().find(b.expect), std::string::npos) << s.error();
  }
  const auto missing = engine::readViewerScript("/nonexistent/script.txt");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("/nonexistent/script.txt"), std::string::npos);
}
