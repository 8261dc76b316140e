// gzip / bzip2 unwrapping (io/Compression.h): detection from the first bytes, then the
// in-memory decompression with a small size limit (the limit's own check is part of the test).
#include "FuzzCommon.h"

#include <atmoglobe/io/Compression.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace atmoglobe;
  const io::Compression c = io::compressionOf(data, size);
  if (c == io::Compression::None) return 0;
  const std::string label = "fuzz.gz";
  constexpr std::size_t kLimit = std::size_t{16} << 20;
  fuzz::checkError(io::decompress(label, data, size, c, kLimit), label);
  fuzz::checkError(io::decompress(label, data, size, c, kLimit, 4096), label);
  return 0;
}
