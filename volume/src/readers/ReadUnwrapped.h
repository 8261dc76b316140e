#pragma once
// The file-path entry of a byte-buffer radar reader: read (unwrapping gzip/bzip2 in memory),
// read the bytes, and name the file and its wrapper in the volume. Private to volume/.
#include <atmoglobe/io/Compression.h>
#include <atmoglobe/volume/RadarVolume.h>

namespace atmoglobe::volume {

template <typename BytesReader>
Result<RadarVolume> readUnwrapped(const std::string& path, const ReadOptions& options, BytesReader readBytes) {
  auto content = io::readFileBytes(path);
  if (!content) return content.forwardError();
  auto vol = readBytes(content->label, content->bytes, options);
  if (vol && content->compression != io::Compression::None) {
    vol->sourcePath = path;
    vol->compression = toString(content->compression);
  }
  return vol;
}

}  // namespace atmoglobe::volume
