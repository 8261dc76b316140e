#include <atmoglobe/bench/ReferenceCache.h>

#include <atmoglobe/bench/Cells.h>
#include <atmoglobe/bench/Format.h>
#include <atmoglobe/engine/VolumeRendererGL.h>
#include <atmoglobe/globe/AtomicFile.h>
#include <atmoglobe/volume/ReferenceRenderer.h>
#include <atmoglobe/volume/TransferFunction.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <ostream>
#include <sstream>
#include <system_error>

namespace atmoglobe::bench {

namespace fs = std::filesystem;

std::string referenceKey(const BenchView& view, int widthPx, int heightPx, const volume::VolumeRenderSettings& s) {
  std::ostringstream k;
  const engine::CameraPose& p = view.pose;
  k << "ref-v1|" << view.volume->cacheIdentity() << "|" << view.volume->fieldName();
  if (view.volume->kind == VolumeKind::Grid) {
    k << "@" << view.volume->gridRead.timeIndex;
    if (view.volume->gridRead.member >= 0) k << "#" << view.volume->gridRead.member;
  }
  k << "|" << formatG(p.latDeg) << "," << formatG(p.lonDeg) << "," << formatG(p.heightMeters) << ","
    << formatG(p.headingDeg) << "," << formatG(p.pitchDeg) << "," << formatG(p.rollDeg) << "|fov "
    << formatG(view.fovYDeg) << "|" << widthPx << "x" << heightPx << "|" << modeName(s.mode) << "|"
    << interpName(s.interpolation) << "|step " << formatG(s.stepMeters) << "|iso " << formatG(s.isoValue) << "|term "
    << formatG(s.earlyTerminationAlpha) << "|tf " << s.transfer.colors.name() << ","
    << formatG(s.transfer.opacityZeroValue) << "," << formatG(s.transfer.opacityFullValue) << ","
    << formatG(s.transfer.maxOpacity) << "," << formatG(s.transfer.opacityReferenceMeters)
    << (view.occludeByEllipsoid ? "|ellipsoid" : "|no-occlusion");
  return k.str();
}

std::uint64_t fnv1a(const std::string& s) {
  // Not the standard FNV-1a offset basis (14695981039346656037): see the header. Do not "fix".
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string referenceFileName(const std::string& key) {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.ref", static_cast<unsigned long long>(fnv1a(key)));
  return name;
}

std::optional<volume::VolumeImage> readCachedReference(const fs::path& file, const std::string& key) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::uint32_t keyLen = 0;
  in.read(reinterpret_cast<char*>(&keyLen), sizeof keyLen);
  if (!in || keyLen > 4096) return std::nullopt;
  std::string k(keyLen, '\0');
  in.read(k.data(), keyLen);
  std::int32_t wh[2] = {0, 0};
  in.read(reinterpret_cast<char*>(wh), sizeof wh);
  if (!in || k != key || wh[0] <= 0 || wh[1] <= 0 || wh[0] > 8192 || wh[1] > 8192) return std::nullopt;
  volume::VolumeImage img;
  img.widthPx = wh[0];
  img.heightPx = wh[1];
  img.rgbaPremultiplied.resize(static_cast<std::size_t>(wh[0]) * static_cast<std::size_t>(wh[1]));
  in.read(reinterpret_cast<char*>(img.rgbaPremultiplied.data()),
          static_cast<std::streamsize>(img.rgbaPremultiplied.size() * sizeof(glm::dvec4)));
  if (!in) return std::nullopt;
  return img;
}

bool writeCachedReference(const fs::path& file, const std::string& key, const volume::VolumeImage& img) {
  std::string bytes;
  auto append = [&](const void* data, std::size_t n) { bytes.append(static_cast<const char*>(data), n); };
  const auto keyLen = static_cast<std::uint32_t>(key.size());
  append(&keyLen, sizeof keyLen);
  append(key.data(), key.size());
  const std::int32_t wh[2] = {img.widthPx, img.heightPx};
  append(wh, sizeof wh);
  append(img.rgbaPremultiplied.data(), img.rgbaPremultiplied.size() * sizeof(glm::dvec4));
  return bool(globe::writeFileAtomic(file.string(), bytes));
}

volume::VolumeRenderSettings referenceSettings(volume::VolumeRenderMode mode, double stepMeters) {
  return referenceSettings(mode, stepMeters, volume::defaultReflectivityTransfer());
}

volume::VolumeRenderSettings referenceSettings(volume::VolumeRenderMode mode, double stepMeters,
                                               const volume::TransferFunction& transfer) {
  volume::VolumeRenderSettings s;
  s.mode = mode;
  s.interpolation = volume::Interpolation::Linear;
  s.stepMeters = stepMeters;
  s.transfer = transfer;
  return s;
}

volume::VolumeImage ReferenceStore::get(const BenchView& view, int widthPx, int heightPx,
                                        const volume::VolumeRenderSettings& s) {
  const std::string key = referenceKey(view, widthPx, heightPx, s);
  const fs::path file = dir / referenceFileName(key);
  if (auto img = readCachedReference(file, key)) {
    ++cached;
    return *img;
  }
  const engine::Camera camera(view.pose, view.fovYDeg, widthPx, heightPx);
  if (log) {
    *log << "  reference " << view.name << " " << modeName(s.mode) << " " << widthPx << "x" << heightPx << " step "
         << s.stepMeters << " m ..." << std::flush;
  }
  const auto t0 = std::chrono::steady_clock::now();
  // A radar: the same image as renderReference(polar, ...) (one PolarSampler layer).
  volume::VolumeImage img = volume::renderReference({volume::ReferenceLayer{&view.volume->referenceSampler(), s}},
                                                    engine::referenceCameraFor(camera), view.occludeByEllipsoid,
                                                    threads);
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  secondsRendering += sec;
  ++rendered;
  if (log) *log << " " << formatG(sec, 4) << " s\n";
  writeCachedReference(file, key, img);  // if it fails, only the next run pays: it renders again
  return img;
}

}  // namespace atmoglobe::bench
