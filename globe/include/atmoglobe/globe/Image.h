#pragma once
// 8-bit RGBA images in memory: decoding (PNG/JPEG via stb_image), PNG writing, sampling.
// GL-free. Row 0 is the TOP row; pixels are tightly packed RGBA (4 bytes per pixel).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmoglobe/globe/Result.h"

namespace atmoglobe::globe {

/// Largest image (in pixels) the decoder accepts: 2^28 px = 1 GiB of RGBA. Larger files are
/// refused with an error instead of attempting an unbounded allocation.
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 28;

struct ImageRGBA8 {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  ///< RGBA, row 0 = top, size width*height*4

  /// Bytes held by the pixel buffer (width * height * 4).
  std::size_t byteSize() const { return pixels.size(); }

  /// A width x height image filled with `fill`.
  static ImageRGBA8 filled(int width, int height, glm::u8vec4 fill);

  /// Pixel (x, y), y from the top; asserts the coordinates are inside.
  glm::u8vec4 at(int x, int y) const;
  void set(int x, int y, glm::u8vec4 rgba);
};

/// The next mip level of `image`, max(1, w / 2) x max(1, h / 2) as GL sizes its levels: each
/// pixel the rounded mean of the 2 x 2 pixels at twice its coordinates (a box filter, what
/// glGenerateMipmap does for RGBA8). A side of 1 pixel averages along the other side only; an
/// odd side's last row or column is left out.
ImageRGBA8 halfSize(const ImageRGBA8& image);

/// Decodes a PNG or JPEG (anything stb_image reads) into RGBA8 (grey/RGB get alpha 255).
/// Errors name the file and give stb's reason (or the OS error when the file can't be read).
Result<ImageRGBA8> decodeImageFile(const std::string& path);

/// Same as decodeImageFile for bytes already in memory; `nameForErrors` names them in messages.
Result<ImageRGBA8> decodeImageMemory(const std::uint8_t* data, std::size_t size, const std::string& nameForErrors);

/// `image` encoded as PNG (stb); errors name `nameForErrors`.
Result<std::vector<std::uint8_t>> encodePng(const ImageRGBA8& image, const std::string& nameForErrors);

/// Writes `image` as a PNG at `path` atomically (globe/AtomicFile.h: hidden temporary beside it,
/// fsync, rename), so a reader never sees a half-written file, even if the process is killed.
Status writePng(const std::string& path, const ImageRGBA8& image);

/// Bilinear sample at texture coordinates (u, v) in [0, 1] (u to the right, v DOWN, row 0 at
/// v = 0). Pixel centres sit at ((i + 0.5) / width, (j + 0.5) / height); coordinates outside the
/// outermost centres clamp to the edge pixels (no wrap). Each channel is interpolated
/// independently (straight, not premultiplied alpha) and rounded to nearest: error <= 0.5 of
/// one 8-bit step against the exact bilinear value.
glm::u8vec4 sampleBilinear(const ImageRGBA8& image, double u, double v);

}  // namespace atmoglobe::globe
