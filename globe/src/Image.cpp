#include "atmoglobe/globe/Image.h"

#include "atmoglobe/globe/AtomicFile.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>

#include <png.h>
#include <stb/stb_image.h>

namespace atmoglobe::globe {

ImageRGBA8 halfSize(const ImageRGBA8& image) {
  assert(image.width > 0 && image.height > 0);
  ImageRGBA8 half;
  half.width = std::max(1, image.width / 2);
  half.height = std::max(1, image.height / 2);
  half.pixels.resize(static_cast<std::size_t>(half.width) * static_cast<std::size_t>(half.height) * 4);
  const std::size_t w = static_cast<std::size_t>(image.width);
  // The second column and row: the next ones, or the same where that side is 1 pixel.
  const std::size_t dx = image.width > 1 ? 4 : 0, dy = image.height > 1 ? w * 4 : 0;
  std::uint8_t* out = half.pixels.data();
  for (int j = 0; j < half.height; ++j)
    for (int i = 0; i < half.width; ++i, out += 4) {
      const std::uint8_t* a =
          &image.pixels[((2 * static_cast<std::size_t>(j)) * w + 2 * static_cast<std::size_t>(i)) * 4];
      const std::uint8_t* b = a + dy;
      for (int c = 0; c < 4; ++c) out[c] = static_cast<std::uint8_t>((a[c] + a[c + dx] + b[c] + b[c + dx] + 2) / 4);
    }
  return half;
}

ImageRGBA8 ImageRGBA8::filled(int width, int height, glm::u8vec4 fill) {
  assert(width >= 0 && height >= 0);
  ImageRGBA8 image;
  image.width = width;
  image.height = height;
  image.pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
  for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
    image.pixels[i] = fill.r;
    image.pixels[i + 1] = fill.g;
    image.pixels[i + 2] = fill.b;
    image.pixels[i + 3] = fill.a;
  }
  return image;
}

glm::u8vec4 ImageRGBA8::at(int x, int y) const {
  assert(x >= 0 && x < width && y >= 0 && y < height);
  const std::uint8_t* p = &pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}

void ImageRGBA8::set(int x, int y, glm::u8vec4 rgba) {
  assert(x >= 0 && x < width && y >= 0 && y < height);
  std::uint8_t* p = &pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x) * 4];
  p[0] = rgba.r;
  p[1] = rgba.g;
  p[2] = rgba.b;
  p[3] = rgba.a;
}

Result<ImageRGBA8> decodeImageMemory(const std::uint8_t* data, std::size_t size, const std::string& nameForErrors) {
  if (size == 0) return makeError(nameForErrors + ": empty file, not an image");
  if (size > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    return makeError(nameForErrors + ": file too large to decode (" + std::to_string(size) + " bytes)");
  }
  const int length = static_cast<int>(size);
  int w = 0, h = 0, channels = 0;
  // Check the header first so a huge image is refused before anything is allocated.
  if (!stbi_info_from_memory(data, length, &w, &h, &channels)) {
    const char* reason = stbi_failure_reason();
    return makeError(nameForErrors + ": not a readable image (" + (reason ? reason : "unknown format") + ")");
  }
  if (w <= 0 || h <= 0 || static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > kMaxImagePixels) {
    return makeError(nameForErrors + ": image of " + std::to_string(w) + " x " + std::to_string(h) +
                     " px is larger than the " + std::to_string(kMaxImagePixels) + " px this decoder accepts");
  }
  // No format stb_image reads packs more than kMaxPixelsPerByte pixels into a byte (PNG: deflate's
  // 1032:1 on 1-bit pixels, ~8256; GIF's 12-bit LZW codes, ~2730; TGA/PSD run lengths, 64; JPEG,
  // a bit per 8x8 block at best, 512), so a header claiming more than that from a small file is
  // corrupt: refused before decoding (fuzz_image: a 21-byte TGA claiming 65535 x 1279 px made
  // stb_image allocate 335 MB and decode for seconds). Small images are always allowed.
  constexpr std::uint64_t kMaxPixelsPerByte = 16384, kAlwaysAllowedPixels = std::uint64_t{1} << 24;
  if (static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) >
      std::max<std::uint64_t>(kAlwaysAllowedPixels, size * kMaxPixelsPerByte)) {
    return makeError(nameForErrors + ": image header claims " + std::to_string(w) + " x " + std::to_string(h) +
                     " px, more than a file of " + std::to_string(size) + " bytes can hold (corrupt)");
  }
  stbi_uc* decoded = stbi_load_from_memory(data, length, &w, &h, &channels, 4);
  if (!decoded) {
    const char* reason = stbi_failure_reason();
    return makeError(nameForErrors + ": cannot decode image (" + (reason ? reason : "unknown error") + ")");
  }
  ImageRGBA8 image;
  image.width = w;
  image.height = h;
  image.pixels.assign(decoded, decoded + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  stbi_image_free(decoded);
  return image;
}

Result<ImageRGBA8> decodeImageFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return makeError(path + ": is a directory, not an image");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return makeError(path + ": cannot open (" + std::strerror(errno) + ")");
  std::vector<std::uint8_t> bytes;
  std::uint8_t buffer[1 << 16];
  bool readError = false;
  for (;;) {
    const std::size_t n = std::fread(buffer, 1, sizeof buffer, f);
    bytes.insert(bytes.end(), buffer, buffer + n);
    if (n < sizeof buffer) {
      readError = std::ferror(f) != 0;
      break;
    }
    // Encoded images beyond 2 GiB are refused by decodeImageMemory anyway: stop reading early.
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) break;
  }
  const int savedErrno = errno;
  std::fclose(f);
  if (readError) return makeError(path + ": read error (" + std::strerror(savedErrno) + ")");
  return decodeImageMemory(bytes.data(), bytes.size(), path);
}

Result<std::vector<std::uint8_t>> encodePng(const ImageRGBA8& image, const std::string& nameForErrors) {
  assert(image.width > 0 && image.height > 0 &&
         image.pixels.size() == static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4);
  // libpng's simplified API in its fast mode, written into memory: 33 ms for the default
  // 1280x720 render against stb's encoder's 160-180 ms (whatever its compression level), the
  // file about as large (575 against 555 kB; medians of 7, side by side, 2026-12-02, this machine).
  char* buffer = nullptr;
  std::size_t length = 0;
  FILE* stream = open_memstream(&buffer, &length);
  if (!stream) return makeError(nameForErrors + ": PNG encoding failed (" + std::strerror(errno) + ")");
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGBA;
  png.flags = PNG_IMAGE_FLAG_FAST;
  const int written = png_image_write_to_stdio(&png, stream, 0, image.pixels.data(), image.width * 4, nullptr);
  const std::string message = png.message;
  png_image_free(&png);
  const bool closed = std::fclose(stream) == 0;  // sets buffer and length
  std::vector<std::uint8_t> encoded;
  if (written && closed && buffer) encoded.assign(buffer, buffer + length);
  std::free(buffer);
  if (!written || !closed)
    return makeError(nameForErrors + ": PNG encoding failed" + (message.empty() ? "" : ": " + message));
  return encoded;
}

Status writePng(const std::string& path, const ImageRGBA8& image) {
  Result<std::vector<std::uint8_t>> encoded = encodePng(image, path);
  if (!encoded) return encoded.forwardError();
  return writeFileAtomic(path, std::string_view(reinterpret_cast<const char*>(encoded->data()), encoded->size()));
}

glm::u8vec4 sampleBilinear(const ImageRGBA8& image, double u, double v) {
  assert(image.width > 0 && image.height > 0);
  // Continuous pixel coordinates with pixel centres at integers.
  const double x = std::clamp(u * image.width - 0.5, 0.0, static_cast<double>(image.width - 1));
  const double y = std::clamp(v * image.height - 0.5, 0.0, static_cast<double>(image.height - 1));
  const int x0 = static_cast<int>(x);
  const int y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, image.width - 1);
  const int y1 = std::min(y0 + 1, image.height - 1);
  const double fx = x - x0;
  const double fy = y - y0;
  const std::size_t w = static_cast<std::size_t>(image.width);
  const std::uint8_t* p00 = &image.pixels[(static_cast<std::size_t>(y0) * w + x0) * 4];
  const std::uint8_t* p10 = &image.pixels[(static_cast<std::size_t>(y0) * w + x1) * 4];
  const std::uint8_t* p01 = &image.pixels[(static_cast<std::size_t>(y1) * w + x0) * 4];
  const std::uint8_t* p11 = &image.pixels[(static_cast<std::size_t>(y1) * w + x1) * 4];
  glm::u8vec4 out;
  for (int c = 0; c < 4; ++c) {
    const double top = p00[c] + (p10[c] - p00[c]) * fx;
    const double bottom = p01[c] + (p11[c] - p01[c]) * fx;
    const double value = top + (bottom - top) * fy;
    out[c] = static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
  }
  return out;
}

}  // namespace atmoglobe::globe
