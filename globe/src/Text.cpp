#include <atmoglobe/globe/Text.h>

#include <cstdio>

namespace atmoglobe {

std::string numberText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

std::string toLowerAscii(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = toLowerAscii(c);
  return out;
}

std::string_view trimAscii(std::string_view text) {
  while (!text.empty() && isSpaceAscii(text.front())) text.remove_prefix(1);
  while (!text.empty() && isSpaceAscii(text.back())) text.remove_suffix(1);
  return text;
}

std::string toLowerAsciiWithoutBlanks(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text)
    if (!isSpaceAscii(c)) out.push_back(toLowerAscii(c));
  return out;
}

bool equalsIgnoringCaseAscii(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (toLowerAscii(a[i]) != toLowerAscii(b[i])) return false;
  return true;
}

}  // namespace atmoglobe
