// Tests of the shared ASCII text helpers (globe/Text.h).
#include <atmoglobe/globe/Text.h>

#include <gtest/gtest.h>

#include <cctype>
#include <string>

namespace atmoglobe {
namespace {

static_assert(toLowerAscii('Q') == 'q');
static_assert(isSpaceAscii('\v') && !isSpaceAscii('_'));

TEST(Text, EveryByteAgreesWithTheCLocale) {
  // The program never calls setlocale, so <cctype> is the "C" locale: the reference here.
  for (int b = 0; b < 256; ++b) {
    const char c = static_cast<char>(b);
    EXPECT_EQ(toLowerAscii(c), static_cast<char>(std::tolower(b))) << b;
    EXPECT_EQ(isSpaceAscii(c), std::isspace(b) != 0) << b;
  }
}

TEST(Text, LowerCase) {
  EXPECT_EQ(toLowerAscii("DBZH Reflectivity_2"), "dbzh reflectivity_2");
  EXPECT_EQ(toLowerAscii(""), "");
  EXPECT_EQ(toLowerAscii("\xC3\x89t\xC3\xA9"), "\xC3\x89t\xC3\xA9");  // "Été" in UTF-8: bytes >= 128 kept
}

TEST(Text, Trim) {
  EXPECT_EQ(trimAscii(" \t\r\n\v\fhPa \r\n"), "hPa");
  EXPECT_EQ(trimAscii("a b"), "a b");
  EXPECT_EQ(trimAscii(" \t "), "");
  EXPECT_EQ(trimAscii(""), "");
  const std::string s = "  kept  ";
  const std::string_view t = trimAscii(s);
  EXPECT_EQ(t.data(), s.data() + 2);  // a view into the argument, no copy
  EXPECT_EQ(t.size(), 4u);
}

TEST(Text, LowerWithoutBlanks) {
  EXPECT_EQ(toLowerAsciiWithoutBlanks(" Geopotential\tHeight "), "geopotentialheight");
  EXPECT_EQ(toLowerAsciiWithoutBlanks("m s-1"), "ms-1");
}

TEST(Text, EqualsIgnoringCase) {
  EXPECT_TRUE(equalsIgnoringCaseAscii("PageUp", "pageup"));
  EXPECT_TRUE(equalsIgnoringCaseAscii("", ""));
  EXPECT_FALSE(equalsIgnoringCaseAscii("Page", "PageUp"));
  EXPECT_FALSE(equalsIgnoringCaseAscii("a_b", "a-b"));
}

}  // namespace
}  // namespace atmoglobe
