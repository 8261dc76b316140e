#pragma once
// gzip- and bzip2-wrapped files, unwrapped in memory (never to disk).
//
// A radar file or grid downloaded as FILE.gz / FILE.bz2 is read as the file inside: the wrapper is
// told from the first bytes (gzip 1f 8b, bzip2 "BZh" + block size '1'..'9'), the content is
// decompressed into memory (zlib, libbz2) and handed to the reader (netCDF-C's nc_open_mem for
// netCDF/HDF5, a byte buffer for the others). Messages name both layers: "FILE (gzip): ...".
//
// Bounds: the decompressed size may not exceed the limit given (kMaxDecompressedBytes by default),
// checked before anything is allocated where the wrapper states a size (gzip's ISIZE trailer, taken
// only as a hint: it is the size modulo 2^32) and while the output grows (doubling, capped), so a
// "zip bomb" stops with an error naming the limit instead of exhausting memory. Concatenated
// members (gzip) and streams (bzip2, as pbzip2 writes them) are read one after another; zero
// padding after the last one is ignored, other trailing bytes are an error.
#include <atmoglobe/globe/Result.h>

#include <cstddef>
#include <string>
#include <vector>

namespace atmoglobe::io {

enum class Compression { None, Gzip, Bzip2 };
/// "none", "gzip", "bzip2".
const char* toString(Compression c);

/// Largest decompressed content read into memory: 2 GiB. Real radar volumes are 1-200 MB
/// uncompressed; a bigger grid is better unpacked first so that it is read lazily.
inline constexpr std::size_t kMaxDecompressedBytes = std::size_t{2} << 30;

/// The wrapper the first bytes announce (None for anything else, including fewer than 3 bytes).
Compression compressionOf(const unsigned char* head, std::size_t size);

/// The wrapper of a file, from its first bytes. Errors: the file cannot be opened or read.
Result<Compression> fileCompression(const std::string& path);

/// "PATH (gzip)" / "PATH (bzip2)"; PATH itself for None. The name messages use for the content.
std::string compressedLabel(const std::string& path, Compression c);

/// Decompresses `size` bytes of `c`-wrapped data. `label` starts every message ("FILE (gzip): ...").
/// At most `maxBytes` are produced (more: an error naming the limit). `stopAfter` < SIZE_MAX stops
/// as soon as that many bytes are out (a peek at the content; truncation past it is not noticed).
Result<std::vector<unsigned char>> decompress(const std::string& label, const unsigned char* data, std::size_t size,
                                              Compression c, std::size_t maxBytes = kMaxDecompressedBytes,
                                              std::size_t stopAfter = static_cast<std::size_t>(-1));

/// A file's bytes, unwrapped when it is compressed.
struct FileBytes {
  Compression compression = Compression::None;
  std::string label;  ///< path, or "path (gzip)" / "path (bzip2)" for messages
  std::vector<unsigned char> bytes;
};

/// Reads a whole file into memory, decompressed if it is gzip/bzip2-wrapped (at most `maxBytes`).
Result<FileBytes> readFileBytes(const std::string& path, std::size_t maxBytes = kMaxDecompressedBytes);

/// The first `count` bytes of a file's content (decompressed if wrapped); fewer if the content is
/// shorter, empty if the file cannot be read or its wrapper is corrupt from the start.
std::vector<unsigned char> peekFileContent(const std::string& path, std::size_t count);

}  // namespace atmoglobe::io
