#include <atmoglobe/io/Compression.h>

#include <bzlib.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace atmoglobe::io {

const char* toString(Compression c) {
  switch (c) {
    case Compression::None: return "none";
    case Compression::Gzip: return "gzip";
    case Compression::Bzip2: return "bzip2";
  }
  return "none";
}

Compression compressionOf(const unsigned char* head, std::size_t size) {
  if (size >= 3 && head[0] == 0x1f && head[1] == 0x8b && head[2] == 8) return Compression::Gzip;  // RFC 1952, deflate
  if (size >= 4 && head[0] == 'B' && head[1] == 'Z' && head[2] == 'h' && head[3] >= '1' && head[3] <= '9')
    return Compression::Bzip2;
  return Compression::None;
}

Result<Compression> fileCompression(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open file for reading");
  std::array<unsigned char, 4> head{};
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  return compressionOf(head.data(), static_cast<std::size_t>(in.gcount()));
}

std::string compressedLabel(const std::string& path, Compression c) {
  if (c == Compression::None) return path;
  return std::string(path).append(" (").append(toString(c)).append(")");
}

namespace {

std::string mib(std::size_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

Error tooBig(const std::string& label, std::size_t maxBytes) {
  return makeError(label + ": decompresses to more than " + mib(maxBytes) +
                   " (the limit for reading a compressed file in memory): a corrupt or malicious file, or "
                   "one to unpack before reading");
}

/// True when every byte of [p, p + n) is zero (tape/block padding after the last member).
bool allZero(const unsigned char* p, std::size_t n) {
  return std::all_of(p, p + n, [](unsigned char b) { return b == 0; });
}

/// Grows `out` (doubling, capped at maxBytes) so that it has room past `produced`; false at the cap.
bool grow(std::vector<unsigned char>& out, std::size_t produced, std::size_t maxBytes) {
  if (produced < out.size()) return true;
  if (out.size() >= maxBytes) return false;
  out.resize(std::min(maxBytes, std::max<std::size_t>(out.size() * 2, 1 << 16)));
  return true;
}

/// At most 1 GiB handed to zlib/libbz2 per call (their counters are 32-bit).
constexpr std::size_t kChunk = std::size_t{1} << 30;
unsigned chunk(std::size_t n) { return static_cast<unsigned>(std::min(n, kChunk)); }

Result<std::vector<unsigned char>> gunzip(const std::string& label, const unsigned char* data, std::size_t size,
                                          std::size_t maxBytes, std::size_t stopAfter) {
  // The ISIZE trailer (uncompressed size mod 2^32) of the last member: a hint for the first
  // allocation, never trusted beyond deflate's largest ratio (1032:1) or the limit.
  std::size_t initial = size * 4;
  if (size >= 18) {
    const unsigned char* t = data + size - 4;
    const std::size_t isize = std::size_t{t[0]} | (std::size_t{t[1]} << 8) | (std::size_t{t[2]} << 16) |
                              (std::size_t{t[3]} << 24);
    if (isize > maxBytes && stopAfter == static_cast<std::size_t>(-1) && size * 1032 >= isize)
      return tooBig(label, maxBytes);
    if (isize > 0 && isize <= size * 1032) initial = isize + 1;  // +1: room to see the stream end
  }
  initial = std::min(std::max<std::size_t>(initial, 1 << 16), maxBytes);
  std::vector<unsigned char> out(initial);
  std::size_t produced = 0;
  std::size_t consumed = 0;
  z_stream zs{};
  if (inflateInit2(&zs, 16 + MAX_WBITS) != Z_OK) return makeError(label + ": cannot initialise zlib");
  struct End {
    z_stream* z;
    ~End() { inflateEnd(z); }
  } end{&zs};
  while (true) {
    // One member.
    bool memberEnded = false;
    while (!memberEnded) {
      if (produced >= stopAfter) {
        out.resize(std::min(produced, stopAfter));
        return out;
      }
      if (!grow(out, produced, maxBytes)) return tooBig(label, maxBytes);
      zs.next_in = const_cast<Bytef*>(data + consumed);
      zs.avail_in = chunk(size - consumed);
      zs.next_out = out.data() + produced;
      zs.avail_out = chunk(out.size() - produced);
      const uInt inBefore = zs.avail_in, outBefore = zs.avail_out;
      const int rc = inflate(&zs, Z_NO_FLUSH);
      consumed += inBefore - zs.avail_in;
      produced += outBefore - zs.avail_out;
      if (rc == Z_STREAM_END) {
        memberEnded = true;
      } else if (rc == Z_BUF_ERROR || (rc == Z_OK && consumed == size && zs.avail_out != 0)) {
        if (consumed == size) return makeError(label + ": the gzip stream ends early (truncated file?)");
        // no progress with room on both sides cannot happen; with a full output, grow and go on
      } else if (rc != Z_OK) {
        return makeError(label + ": corrupt gzip data (zlib: " + std::string(zs.msg ? zs.msg : zError(rc)) + ")");
      }
    }
    if (consumed == size || allZero(data + consumed, size - consumed)) break;
    if (compressionOf(data + consumed, size - consumed) != Compression::Gzip)
      return makeError(label + ": " + std::to_string(size - consumed) +
                       " bytes after the end of the gzip stream that are not another gzip member");
    if (inflateReset(&zs) != Z_OK) return makeError(label + ": cannot reset zlib");
  }
  out.resize(std::min(produced, stopAfter));
  return out;
}

Result<std::vector<unsigned char>> bunzip2(const std::string& label, const unsigned char* data, std::size_t size,
                                           std::size_t maxBytes, std::size_t stopAfter) {
  // bzip2 states no size: start at 8x (typical radar/netCDF ratios are 3-20), grow by doubling.
  std::vector<unsigned char> out(std::min(std::max<std::size_t>(size * 8, 1 << 16), maxBytes));
  std::size_t produced = 0;
  std::size_t consumed = 0;
  while (true) {
    bz_stream bz{};
    if (BZ2_bzDecompressInit(&bz, 0, 0) != BZ_OK) return makeError(label + ": cannot initialise libbz2");
    struct End {
      bz_stream* b;
      ~End() { BZ2_bzDecompressEnd(b); }
    } end{&bz};
    bool streamEnded = false;
    while (!streamEnded) {
      if (produced >= stopAfter) {
        out.resize(std::min(produced, stopAfter));
        return out;
      }
      if (!grow(out, produced, maxBytes)) return tooBig(label, maxBytes);
      bz.next_in = const_cast<char*>(reinterpret_cast<const char*>(data + consumed));
      bz.avail_in = chunk(size - consumed);
      bz.next_out = reinterpret_cast<char*>(out.data() + produced);
      bz.avail_out = chunk(out.size() - produced);
      const unsigned inBefore = bz.avail_in, outBefore = bz.avail_out;
      const int rc = BZ2_bzDecompress(&bz);
      consumed += inBefore - bz.avail_in;
      produced += outBefore - bz.avail_out;
      if (rc == BZ_STREAM_END) {
        streamEnded = true;
      } else if (rc != BZ_OK) {
        return makeError(label + ": corrupt bzip2 data (libbz2 error " + std::to_string(rc) + ")");
      } else if (consumed == size && bz.avail_out != 0) {
        return makeError(label + ": the bzip2 stream ends early (truncated file?)");
      }
    }
    if (consumed == size || allZero(data + consumed, size - consumed)) break;
    if (compressionOf(data + consumed, size - consumed) != Compression::Bzip2)
      return makeError(label + ": " + std::to_string(size - consumed) +
                       " bytes after the end of the bzip2 stream that are not another bzip2 stream");
  }
  out.resize(std::min(produced, stopAfter));
  return out;
}

}  // namespace

Result<std::vector<unsigned char>> decompress(const std::string& label, const unsigned char* data, std::size_t size,
                                              Compression c, std::size_t maxBytes, std::size_t stopAfter) {
  switch (c) {
    case Compression::Gzip: return gunzip(label, data, size, maxBytes, stopAfter);
    case Compression::Bzip2: return bunzip2(label, data, size, maxBytes, stopAfter);
    case Compression::None: break;
  }
  const std::size_t n = std::min({size, maxBytes, stopAfter});
  return std::vector<unsigned char>(data, data + n);
}

namespace {
Result<std::vector<unsigned char>> readRaw(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return makeError(path + ": no such file (or not a regular file)");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return makeError(path + ": cannot read file: " + ec.message());
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path + ": cannot open file for reading");
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))
    return makeError(path + ": read error");
  return bytes;
}
}  // namespace

Result<FileBytes> readFileBytes(const std::string& path, std::size_t maxBytes) {
  auto raw = readRaw(path);
  if (!raw) return raw.forwardError();
  FileBytes fb;
  fb.compression = compressionOf(raw->data(), raw->size());
  fb.label = compressedLabel(path, fb.compression);
  if (fb.compression == Compression::None) {
    fb.bytes = std::move(*raw);
    return fb;
  }
  auto out = decompress(fb.label, raw->data(), raw->size(), fb.compression, maxBytes);
  if (!out) return out.forwardError();
  fb.bytes = std::move(*out);
  return fb;
}

std::vector<unsigned char> peekFileContent(const std::string& path, std::size_t count) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  // Compressed data is rarely larger than its content; 64 KiB more covers headers and small blocks.
  const std::size_t want = count + (std::size_t{1} << 16);
  std::vector<unsigned char> head(want);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(want));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const Compression c = compressionOf(head.data(), head.size());
  if (c == Compression::None) {
    head.resize(std::min(head.size(), count));
    return head;
  }
  // A compressed file: read it all (bzip2 blocks are up to 900 kB) and stop after `count` bytes.
  auto raw = readRaw(path);
  if (!raw) return {};
  auto out = decompress(path, raw->data(), raw->size(), c, kMaxDecompressedBytes, count);
  return out ? std::move(*out) : std::vector<unsigned char>();
}

}  // namespace atmoglobe::io
