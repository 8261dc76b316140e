#pragma once
// GDAL, loaded when first needed (dlopen) rather than with the program: it brings 113 libraries,
// all bound at load (BIND_NOW), which cost every process 60 ms at start on the 2-core machine
// whether it reads a vector file or draws contours or not (docs/bench-globe.md). GDAL's headers
// give the types and declarations; the calls go through the table below. Private to map.
#include <gdal.h>
#include <gdal_alg.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include "atmoglobe/globe/Result.h"

namespace atmoglobe::map::detail {

// Every GDAL function map calls.
#define ATMOGLOBE_GDAL_FUNCTIONS(X)     \
  X(GDALAllRegister)                    \
  X(GDALClose)                          \
  X(GDALContourGenerateEx)              \
  X(GDALCreate)                         \
  X(GDALDatasetCreateLayer)             \
  X(GDALDatasetGetLayer)                \
  X(GDALDatasetGetLayerCount)           \
  X(GDALGetDriverByName)                \
  X(GDALGetDriverLongName)              \
  X(GDALGetDriverShortName)             \
  X(GDALGetRasterBand)                  \
  X(GDALIdentifyDriverEx)               \
  X(GDALOpenEx)                         \
  X(GDALRasterIO)                       \
  X(GDALSetGeoTransform)                \
  X(GDALSetRasterNoDataValue)           \
  X(CPLGetErrorHandlerUserData)         \
  X(CPLGetLastErrorMsg)                 \
  X(CPLPopErrorHandler)                 \
  X(CPLPushErrorHandler)                \
  X(CPLPushErrorHandlerEx)              \
  X(CPLQuietErrorHandler)               \
  X(OCTDestroyCoordinateTransformation) \
  X(OCTNewCoordinateTransformation)     \
  X(OCTTransformEx)                     \
  X(OGR_F_Destroy)                      \
  X(OGR_F_GetFieldAsDouble)             \
  X(OGR_F_GetGeometryRef)               \
  X(OGR_Fld_Create)                     \
  X(OGR_Fld_Destroy)                    \
  X(OGR_G_DestroyGeometry)              \
  X(OGR_G_GetGeometryCount)             \
  X(OGR_G_GetGeometryRef)               \
  X(OGR_G_GetGeometryType)              \
  X(OGR_G_GetLinearGeometry)            \
  X(OGR_G_GetPointCount)                \
  X(OGR_G_GetX)                         \
  X(OGR_G_GetY)                         \
  X(OGR_GT_Flatten)                     \
  X(OGR_GT_IsCurve)                     \
  X(OGR_GT_IsSurface)                   \
  X(OGR_L_CreateField)                  \
  X(OGR_L_GetName)                      \
  X(OGR_L_GetNextFeature)               \
  X(OGR_L_GetSpatialRef)                \
  X(OGR_L_ResetReading)                 \
  X(OSRClone)                           \
  X(OSRDestroySpatialReference)         \
  X(OSRGetName)                         \
  X(OSRImportFromEPSG)                  \
  X(OSRNewSpatialReference)             \
  X(OSRSetAxisMappingStrategy)

struct GdalApi {
#define ATMOGLOBE_GDAL_POINTER(name) decltype(&::name) name = nullptr;
  ATMOGLOBE_GDAL_FUNCTIONS(ATMOGLOBE_GDAL_POINTER)
#undef ATMOGLOBE_GDAL_POINTER
};

/// Loads GDAL (once, from any thread), finds every function of the table and registers its
/// drivers. The error names the library and what is missing: a program that never reads a
/// vector file or draws contours runs without GDAL installed.
Status loadGdal();
/// The table; only after loadGdal succeeded.
const GdalApi& gdal();

}  // namespace atmoglobe::map::detail
