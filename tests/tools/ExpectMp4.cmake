# Runs CMD ARGS (a render that writes an MP4), then checks the MP4 with ffprobe: one H.264 video
# stream of WIDTH x HEIGHT with FRAMES frames (decoded and counted, not read from the header), and
# no temporary file left beside it.
execute_process(COMMAND ${CMD} ${ARGS} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("exit: ${rc}\nstdout: ${out}\nstderr: ${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "expected exit 0")
endif()
if(NOT EXISTS "${MP4}")
  message(FATAL_ERROR "${MP4} was not written")
endif()
execute_process(COMMAND ${FFPROBE} -v error -count_frames -select_streams v:0
                        -show_entries stream=codec_name,width,height,nb_read_frames -of csv=p=0 ${MP4}
                RESULT_VARIABLE prc OUTPUT_VARIABLE probe ERROR_VARIABLE perr OUTPUT_STRIP_TRAILING_WHITESPACE)
message("ffprobe: ${probe} ${perr}")
if(NOT prc EQUAL 0)
  message(FATAL_ERROR "ffprobe could not read ${MP4}: ${perr}")
endif()
if(NOT probe STREQUAL "h264,${WIDTH},${HEIGHT},${FRAMES}")
  message(FATAL_ERROR "expected h264,${WIDTH},${HEIGHT},${FRAMES} (codec, width, height, frames); got '${probe}'")
endif()
get_filename_component(dir "${MP4}" DIRECTORY)
get_filename_component(name "${MP4}" NAME)
file(GLOB leftovers "${dir}/.${name}.tmp*")
if(leftovers)
  message(FATAL_ERROR "temporary files left: ${leftovers}")
endif()
