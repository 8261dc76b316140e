#pragma once
// Export of radar sweeps as georeferenced textured cones (the legacy 3-D radar view) to glTF 2.0
// (.glb / .gltf), COLLADA 1.4.1 (.dae), KML (.kml + models) and KMZ, plus a 3D Tiles tileset.
//
// Georeference (glTF 2.0 specification and 3D Tiles 1.0, Khronos / OGC 18-053r2; COLLADA 1.4.1,
// Khronos; OGC KML 2.2, OGC 07-147r2, and Google's KML Reference for <Model>):
//   - glTF: vertices in the local ENU frame at the antenna stored Y-up as (east, up, -north);
//     the root node's matrix, computed in double, maps them into a Y-up Earth-fixed world
//     (x, y, z) = (X_ecef, Z_ecef, -Y_ecef): exactly what the 3D Tiles y-up -> z-up rotation
//     turns back into ECEF, so the same .glb lands right in CesiumJS and in plain glTF viewers.
//   - 3D Tiles (exportConesTileset): the tile's content is the cones WITHOUT the node matrix and
//     the tileset's root transform is the ENU -> ECEF matrix (the y-up -> z-up rotation applies).
//   - COLLADA: ENU metres, <up_axis>Z_UP</up_axis>, <unit meter="1"/>; texture t = 1 - v.
//   - KML: one <Model> per sweep (each within Google Earth's 21,845 triangles), <Location> at the
//     antenna with altitudeMode absolute and the antenna altitude above mean sea level (EGM96),
//     <Orientation> heading 0 tilt 0 roll 0, <Scale> 1 1 1.
// Every file is written atomically (AtomicFile.h): a failed export leaves no half-written file.
#include <atmoglobe/globe/Result.h>
#include <atmoglobe/volume/ColorTable.h>
#include <atmoglobe/volume/ConeMesh.h>
#include <atmoglobe/volume/Geolocation.h>
#include <atmoglobe/volume/RadarVolume.h>
#include <atmoglobe/volume/SweepImage.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace atmoglobe::volume {

struct ConeExportOptions {
  std::vector<int> sweepIndices;  ///< indices into RadarVolume::sweeps; empty: every PPI sweep
  double maxRangeMeters = std::numeric_limits<double>::infinity();  ///< last gate used (m)
  ConeMeshOptions mesh;                                             ///< straight/bent, beam model, triangle budget
  bool useGeoid = true;  ///< MSL antenna heights -> ellipsoid with EGM96 (resolveSite)
};

struct Cone {
  std::size_t sweepIndex = 0;  ///< index in RadarVolume::sweeps
  ConeMesh mesh;
  SweepImage image;
  std::vector<std::uint8_t> png;  ///< the image as PNG
};

struct ConeScene {
  std::string title;                    ///< "SITE time field", for names in the files
  SiteResolution site;                  ///< antenna on the ellipsoid
  double antennaAltitudeMslMeters = 0;  ///< antenna height above mean sea level (KML altitude)
  glm::dmat4 enuToEcef{1.0};            ///< local ENU at the antenna -> ECEF (m), double
  bool straight = false;
  std::vector<Cone> cones;
};

/// Builds the cones of the selected sweeps. Errors (naming the file): a sweep index out of range
/// or not a PPI, no PPI sweep, a sweep with no rays / no gates / no values / bad gate geometry
/// or non-finite angles, no gate within maxRangeMeters, a site that resolveSite rejects.
Result<ConeScene> buildConeScene(const RadarVolume& volume, const ColorTable& colors, const ConeExportOptions& options);
/// The same with the site already resolved (volume::loadRadar's LoadedRadar::site);
/// options.useGeoid is not used.
Result<ConeScene> buildConeScene(const RadarVolume& volume, const SiteResolution& site, const ColorTable& colors,
                                 const ConeExportOptions& options);

enum class ConeFormat { Glb, Gltf, Collada, Kml, Kmz };
/// From the output file's extension (.glb .gltf .dae .kml .kmz, case-insensitive).
Result<ConeFormat> coneFormatFromPath(const std::string& path);

/// Writes the scene to `outPath` in the format its extension names. Files written:
///   .glb / .gltf: that file (.gltf embeds buffer and PNGs as data: URIs);
///   .dae: that file (one node + geometry per sweep) and STEM_sweepNN.png beside it;
///   .kml: that file and STEM_files/sweepNN.dae + sweepNN.png (directory created);
///   .kmz: one zip (libzip, ZipArchive.h) with doc.kml first, models/sweepNN.dae (deflated) and
///         models/sweepNN.png (stored: PNG is compressed already).
/// All files are staged to temporaries and renamed into place only after every write succeeded.
/// Returns the list of files written.
Result<std::vector<std::string>> exportCones(const ConeScene& scene, const std::string& outPath);

/// Writes DIR/tileset.json (3D Tiles 1.1, glTF content) and DIR/cones.glb; creates DIR.
Result<std::vector<std::string>> exportConesTileset(const ConeScene& scene, const std::string& dir);

// --- encoders (in memory; exposed for tests) ---

/// glTF 2.0 with every sweep as a mesh node under one root. binary: GLB container, else JSON with
/// data: URIs. withEcefMatrix: the root node carries the ENU -> Y-up Earth-fixed matrix (see top);
/// without it the content stays in the local frame (3D Tiles content).
std::string encodeConesGltf(const ConeScene& scene, bool binary, bool withEcefMatrix);

/// Column-major 4x4 of the glTF root node: glTF local (east, up, -north) -> Y-up Earth-fixed world.
glm::dmat4 gltfRootMatrix(const ConeScene& scene);

/// COLLADA 1.4.1 document with the given cones (indices into scene.cones), each textured with the
/// image at textureUris[i] (relative URI).
std::string encodeConesCollada(const ConeScene& scene, const std::vector<std::size_t>& cones,
                               const std::vector<std::string>& textureUris);

/// KML document with one Placemark/Model per cone, model i at daeHrefs[i].
std::string encodeConesKml(const ConeScene& scene, const std::vector<std::string>& daeHrefs);

/// 3D Tiles 1.1 tileset.json whose root content is `contentUri`.
std::string encodeConesTileset(const ConeScene& scene, const std::string& contentUri);

/// "sweep07": the per-sweep file stem.
std::string sweepStem(std::size_t sweepIndex);

}  // namespace atmoglobe::volume
