// atmoglobe_image_check: what a CLI test's picture shows, measured against another picture.
//
//   atmoglobe_image_check A.png B.png [--box X0,Y0,X1,Y1] [--min F] [--max F] [--threshold T]
//
// Counts the pixels inside the box (fractions of the width and height, 0,0 = top left; default the
// whole image) where A and B differ by more than T (0..255, default 24) in any of R, G, B, and
// passes when that fraction of the box lies in [min, max] (defaults 0 and 1). Used to check that a
// radar layer draws inside the screen region where its storm is and leaves the rest of the globe
// alone, that a legend is drawn, and that the frames of a time series differ (tests/tools).
// Prints the fraction; exit 0 pass, 1 fail, 2 bad use or unreadable file.
#include <atmoglobe/globe/Image.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

using namespace atmoglobe;

namespace {

int usage(const std::string& why) {
  std::fprintf(stderr,
               "atmoglobe_image_check: %s\nusage: atmoglobe_image_check A.png B.png [--box X0,Y0,X1,Y1] "
               "[--min F] [--max F] [--threshold T]\n",
               why.c_str());
  return 2;
}

bool parseNumber(const std::string& text, double& out) {
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0';
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() < 2) return usage("two images are needed");
  double box[4] = {0.0, 0.0, 1.0, 1.0};
  double minFraction = 0.0, maxFraction = 1.0, threshold = 24.0;
  for (std::size_t i = 2; i < args.size(); i += 2) {
    if (i + 1 >= args.size()) return usage(args[i] + " needs a value");
    const std::string& key = args[i];
    const std::string& value = args[i + 1];
    bool ok = true;
    if (key == "--box") {
      std::stringstream in(value);
      std::string part;
      for (int k = 0; k < 4; ++k) ok = ok && std::getline(in, part, ',') && parseNumber(part, box[k]);
      ok = ok && box[0] >= 0.0 && box[1] >= 0.0 && box[2] <= 1.0 && box[3] <= 1.0 && box[0] < box[2] && box[1] < box[3];
    } else if (key == "--min") {
      ok = parseNumber(value, minFraction);
    } else if (key == "--max") {
      ok = parseNumber(value, maxFraction);
    } else if (key == "--threshold") {
      ok = parseNumber(value, threshold);
    } else {
      return usage("unknown option " + key);
    }
    if (!ok) return usage("bad value for " + key + ": " + value);
  }
  auto a = globe::decodeImageFile(args[0]);
  if (!a) return usage(a.error());
  auto b = globe::decodeImageFile(args[1]);
  if (!b) return usage(b.error());
  if (a->width != b->width || a->height != b->height) return usage(args[0] + " and " + args[1] + " differ in size");
  const int x0 = static_cast<int>(box[0] * a->width), x1 = std::max(x0 + 1, static_cast<int>(box[2] * a->width));
  const int y0 = static_cast<int>(box[1] * a->height), y1 = std::max(y0 + 1, static_cast<int>(box[3] * a->height));
  long differing = 0, total = 0;
  for (int y = y0; y < y1 && y < a->height; ++y)
    for (int x = x0; x < x1 && x < a->width; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * a->width + x) * 4;
      int d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a->pixels[i + c]) - int(b->pixels[i + c])));
      differing += d > threshold ? 1 : 0;
      ++total;
    }
  const double fraction = total > 0 ? static_cast<double>(differing) / static_cast<double>(total) : 0.0;
  std::printf("%s vs %s, box %.3g,%.3g,%.3g,%.3g (%ld px): %.4f of the pixels differ by more than %.0f\n",
              args[0].c_str(), args[1].c_str(), box[0], box[1], box[2], box[3], total, fraction, threshold);
  if (fraction < minFraction || fraction > maxFraction) {
    std::printf("FAIL: expected a fraction in [%g, %g]\n", minFraction, maxFraction);
    return 1;
  }
  return 0;
}
