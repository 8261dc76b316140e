#pragma once
// NEXRAD Level II (Archive II, message 31) reader.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/RadarVolume.h>

#include <string>

namespace atmoglobe::volume {

/// Reads a NEXRAD Level II Archive II file (bzip2-compressed LDM records of message 31).
Result<RadarVolume> readNexradLevel2(const std::string& path, const ReadOptions& options);

}  // namespace atmoglobe::volume
