#include <atmoglobe/bench/Format.h>

#include <cstdio>

namespace atmoglobe::bench {

std::string formatG(double v, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", precision, v);
  return buf;
}

}  // namespace atmoglobe::bench
