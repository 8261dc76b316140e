# GDAL is loaded only by a command that reads a vector file or draws contours (map/src/GdalLibrary.h):
# a render without an overlay must not load it, one with an overlay must. The dynamic loader's own
# log (LD_DEBUG=files, on stderr) says which libraries a process opened.
# -DCMD=atmoglobe -DIMAGERY=DIR -DOVERLAY=FILE.geojson -DOUT=DIR
foreach(case plain overlay)
  set(args render --imagery ${IMAGERY} --camera 35.33,-97.28,8e5,0,-90,0 --size 64x36 --no-legend -o ${OUT}/gdal_${case}.png)
  if(case STREQUAL "overlay")
    list(APPEND args --overlay ${OVERLAY})
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E env LD_DEBUG=files ${CMD} ${args}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${case}: atmoglobe render failed (${rc}):\n${err}")
  endif()
  string(REGEX MATCH "file=[^ ]*libgdal[^ ]*" gdal "${err}")
  if(case STREQUAL "plain" AND gdal)
    message(FATAL_ERROR "a render without an overlay loaded GDAL (${gdal})")
  elseif(case STREQUAL "overlay" AND NOT gdal)
    message(FATAL_ERROR "a render with an overlay did not load GDAL, yet drew it?\n${err}")
  endif()
  message(STATUS "${case}: ${gdal}")
endforeach()
