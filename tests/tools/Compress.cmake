# Writes a gzip- or bzip2-compressed copy of IN to OUTPUT (COMPRESSION GZip or BZip2), the way a
# user receives FILE.gz: CMake's archive support with the raw format compresses one file as it is.
file(ARCHIVE_CREATE OUTPUT "${OUTPUT}" PATHS "${IN}" FORMAT raw COMPRESSION ${COMPRESSION})
if(NOT EXISTS "${OUTPUT}")
  message(FATAL_ERROR "could not write ${OUTPUT}")
endif()
