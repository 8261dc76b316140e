// Scene building and file output for the radar cone export (encoders in ConeExport*.cpp).
#include <atmoglobe/volume/ConeExport.h>

#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/globe/Text.h>
#include <atmoglobe/volume/AtomicFile.h>
#include <atmoglobe/volume/Geoid.h>
#include <atmoglobe/volume/ZipArchive.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <system_error>

namespace atmoglobe::volume {

namespace {

std::string describeSweep(const RadarVolume& v, std::size_t k) { return v.sourcePath + ": sweep " + std::to_string(k); }

Status checkSweep(const RadarVolume& v, std::size_t k) {
  const Sweep& s = v.sweeps[k];
  const std::string what = describeSweep(v, k);
  if (s.mode != SweepMode::Ppi) return makeError(what + " is not a PPI (" + toString(s.mode) + "): no cone to draw");
  if (s.rayCount() == 0) return makeError(what + " has no rays");
  if (s.gateCount == 0) return makeError(what + " has no gates");
  if (s.values.size() != s.rayCount() * static_cast<std::size_t>(s.gateCount)) {
    return makeError(what + ": field values not loaded (" + std::to_string(s.values.size()) + " values for " +
                     std::to_string(s.rayCount()) + " rays x " + std::to_string(s.gateCount) + " gates)");
  }
  if (!std::isfinite(s.gateSpacingMeters) || s.gateSpacingMeters <= 0.0)
    return makeError(what + ": gate spacing " + std::to_string(s.gateSpacingMeters) + " m is not positive");
  if (!std::isfinite(s.firstGateRangeMeters) || s.firstGateRangeMeters < 0.0)
    return makeError(what + ": first gate range " + std::to_string(s.firstGateRangeMeters) + " m is not valid");
  if (!std::isfinite(s.fixedAngleDeg) || s.fixedAngleDeg <= -90.0 || s.fixedAngleDeg >= 90.0)
    return makeError(what + ": elevation " + std::to_string(s.fixedAngleDeg) + " deg is not in (-90, 90)");
  for (float a : s.azimuthDeg) {
    if (!std::isfinite(a)) return makeError(what + ": a ray has a non-finite azimuth");
  }
  return Ok{};
}

std::string lowerExt(const std::string& path) { return toLowerAscii(std::filesystem::path(path).extension().string()); }

/// The options checked and the sweeps chosen (indices into volume.sweeps), each checked.
Result<std::vector<std::size_t>> chooseSweeps(const RadarVolume& volume, const ColorTable& colors,
                                              const ConeExportOptions& options) {
  if (colors.empty()) return makeError("colour table '" + colors.name() + "' has no entries");
  if (!(options.maxRangeMeters > 0.0)) return makeError("--max-range must be positive");
  if (!options.mesh.straight) {
    if (Status s = validateBeamModel(options.mesh.beam, "beam model"); !s) return s.forwardError();
  }
  std::vector<std::size_t> chosen;
  if (options.sweepIndices.empty()) {
    for (std::size_t k = 0; k < volume.sweeps.size(); ++k) {
      if (volume.sweeps[k].mode == SweepMode::Ppi) chosen.push_back(k);
    }
    if (chosen.empty()) return makeError(volume.sourcePath + ": no PPI sweep: nothing to draw as cones");
  } else {
    for (int k : options.sweepIndices) {
      if (k < 0 || static_cast<std::size_t>(k) >= volume.sweeps.size()) {
        return makeError(volume.sourcePath + ": sweep " + std::to_string(k) + " out of range (the volume has " +
                         std::to_string(volume.sweeps.size()) + " sweeps, 0.." +
                         std::to_string(static_cast<long>(volume.sweeps.size()) - 1) + ")");
      }
      if (std::find(chosen.begin(), chosen.end(), static_cast<std::size_t>(k)) == chosen.end())
        chosen.push_back(static_cast<std::size_t>(k));
    }
  }
  for (std::size_t k : chosen) {
    if (Status s = checkSweep(volume, k); !s) return s.forwardError();
  }
  return chosen;
}

Result<ConeScene> assembleConeScene(const RadarVolume& volume, const SiteResolution& site,
                                    const std::vector<std::size_t>& chosen, const ColorTable& colors,
                                    const ConeExportOptions& options) {
  ConeScene scene;
  scene.site = site;
  // KML wants the altitude above mean sea level (Google Earth's EGM96 surface).
  if (volume.site.heightDatum == HeightDatum::MeanSeaLevel) {
    scene.antennaAltitudeMslMeters = volume.site.antennaHeightMeters;
  } else {
    const Result<GeoidGrid>& geoid = defaultEgm96Grid();
    scene.antennaAltitudeMslMeters = volume.site.antennaHeightMeters -
                                     (geoid ? geoid->undulationMeters(volume.site.latDeg, volume.site.lonDeg) : 0.0);
  }
  scene.enuToEcef = globe::enuToEcef(
      globe::Geodetic{scene.site.site.latDeg, scene.site.site.lonDeg, scene.site.site.antennaHeightEllipsoidMeters});
  scene.straight = options.mesh.straight;
  scene.title =
      (volume.site.name.empty() && volume.site.placeName.empty() ? std::string("radar") : siteTitle(volume.site)) +
      (volume.timeIso8601.empty() ? "" : " " + volume.timeIso8601) +
      (volume.loadedField.name.empty() ? "" : " " + volume.loadedField.name);

  for (std::size_t k : chosen) {
    const Sweep& s = volume.sweeps[k];
    // Gates whose centre is within the maximum range.
    std::uint32_t gates = s.gateCount;
    if (std::isfinite(options.maxRangeMeters)) {
      const double n = std::floor((options.maxRangeMeters - s.firstGateRangeMeters) / s.gateSpacingMeters) + 1.0;
      gates = static_cast<std::uint32_t>(std::clamp(n, 0.0, static_cast<double>(s.gateCount)));
    }
    if (gates == 0) {
      return makeError(describeSweep(volume, k) + ": no gate within --max-range (first gate at " +
                       std::to_string(s.firstGateRangeMeters) + " m)");
    }
    Cone cone;
    cone.sweepIndex = k;
    cone.image = makeSweepImage(s, colors, gates);
    cone.mesh = buildConeMesh(scene.site.site, s, cone.image, options.mesh);
    cone.png = encodeSweepImagePng(cone.image);
    if (cone.png.empty()) return makeError(describeSweep(volume, k) + ": PNG encoding of the sweep image failed");
    scene.cones.push_back(std::move(cone));
  }
  return scene;
}

}  // namespace

Result<ConeScene> buildConeScene(const RadarVolume& volume, const ColorTable& colors,
                                 const ConeExportOptions& options) {
  Result<std::vector<std::size_t>> chosen = chooseSweeps(volume, colors, options);
  if (!chosen) return chosen.forwardError();
  Result<SiteResolution> site = resolveSite(volume.site, options.useGeoid);
  if (!site) return makeError(volume.sourcePath + ": " + site.error());
  return assembleConeScene(volume, *site, *chosen, colors, options);
}

Result<ConeScene> buildConeScene(const RadarVolume& volume, const SiteResolution& site, const ColorTable& colors,
                                 const ConeExportOptions& options) {
  Result<std::vector<std::size_t>> chosen = chooseSweeps(volume, colors, options);
  if (!chosen) return chosen.forwardError();
  return assembleConeScene(volume, site, *chosen, colors, options);
}

Result<ConeFormat> coneFormatFromPath(const std::string& path) {
  const std::string e = lowerExt(path);
  if (e == ".glb") return ConeFormat::Glb;
  if (e == ".gltf") return ConeFormat::Gltf;
  if (e == ".dae") return ConeFormat::Collada;
  if (e == ".kml") return ConeFormat::Kml;
  if (e == ".kmz") return ConeFormat::Kmz;
  return makeError(path + ": unknown output format '" + e + "' (use .glb, .gltf, .dae, .kml or .kmz)");
}

Result<std::vector<std::string>> exportCones(const ConeScene& scene, const std::string& outPath) {
  Result<ConeFormat> format = coneFormatFromPath(outPath);
  if (!format) return format.forwardError();
  const std::filesystem::path out(outPath);
  const std::string stem = out.stem().string();
  const std::filesystem::path dir = out.parent_path();
  auto pngOf = [](const Cone& c) { return std::string(c.png.begin(), c.png.end()); };

  AtomicFileSet files;
  std::vector<std::string> written;
  auto add = [&](const std::filesystem::path& p, std::string_view bytes) -> Status {
    if (Status s = files.add(p.string(), bytes); !s) return s;
    written.push_back(p.string());
    return Ok{};
  };
  std::vector<std::size_t> all(scene.cones.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;

  switch (format.value()) {
    case ConeFormat::Glb:
    case ConeFormat::Gltf: {
      Status s = add(out, encodeConesGltf(scene, format.value() == ConeFormat::Glb, true));
      if (!s) return s.forwardError();
      break;
    }
    case ConeFormat::Collada: {
      std::vector<std::string> uris;
      for (const Cone& c : scene.cones) {
        const std::string png = stem + "_" + sweepStem(c.sweepIndex) + ".png";
        uris.push_back(png);
        if (Status s = add(dir / png, pngOf(c)); !s) return s.forwardError();
      }
      if (Status s = add(out, encodeConesCollada(scene, all, uris)); !s) return s.forwardError();
      break;
    }
    case ConeFormat::Kml: {
      const std::string sub = stem + "_files";
      std::error_code ec;
      std::filesystem::create_directories(dir / sub, ec);
      if (ec) return makeError((dir / sub).string() + ": cannot create directory: " + ec.message());
      std::vector<std::string> hrefs;
      for (const Cone& c : scene.cones) {
        const std::string st = sweepStem(c.sweepIndex);
        if (Status s = add(dir / sub / (st + ".png"), pngOf(c)); !s) return s.forwardError();
        if (Status s =
                add(dir / sub / (st + ".dae"),
                    encodeConesCollada(scene, {static_cast<std::size_t>(&c - scene.cones.data())}, {st + ".png"}));
            !s)
          return s.forwardError();
        hrefs.push_back(sub + "/" + st + ".dae");
      }
      if (Status s = add(out, encodeConesKml(scene, hrefs)); !s) return s.forwardError();
      break;
    }
    case ConeFormat::Kmz: {
      std::vector<ZipEntry> entries;
      std::vector<std::string> hrefs;
      for (std::size_t i = 0; i < scene.cones.size(); ++i) {
        const std::string st = sweepStem(scene.cones[i].sweepIndex);
        hrefs.push_back("models/" + st + ".dae");
      }
      entries.push_back({"doc.kml", encodeConesKml(scene, hrefs), true});  // first entry, as Google Earth expects
      for (std::size_t i = 0; i < scene.cones.size(); ++i) {
        const std::string st = sweepStem(scene.cones[i].sweepIndex);
        entries.push_back({"models/" + st + ".dae", encodeConesCollada(scene, {i}, {st + ".png"}), true});
        entries.push_back({"models/" + st + ".png", pngOf(scene.cones[i]), false});
      }
      // One file: libzip builds it at a temporary name, then it is renamed into place.
      if (Status s = writeZipArchiveAtomic(out.string(), entries); !s) return s.forwardError();
      written.push_back(out.string());
      break;
    }
  }
  if (Status s = files.commit(); !s) return s.forwardError();
  return written;
}

Result<std::vector<std::string>> exportConesTileset(const ConeScene& scene, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return makeError(dir + ": cannot create tileset directory: " + ec.message());
  const std::filesystem::path d(dir);
  AtomicFileSet files;
  const std::string glb = (d / "cones.glb").string(), json = (d / "tileset.json").string();
  if (Status s = files.add(glb, encodeConesGltf(scene, true, false)); !s) return s.forwardError();
  if (Status s = files.add(json, encodeConesTileset(scene, "cones.glb")); !s) return s.forwardError();
  if (Status s = files.commit(); !s) return s.forwardError();
  return std::vector<std::string>{glb, json};
}

}  // namespace atmoglobe::volume
