# The viewer's "Save scene" (Ctrl+S) against `render`: VIEW (an xvfb-run command line) replays a
# script that moves the camera and the time, saves the scene to SCENE and takes a screenshot SHOT
# (no panel); RENDER renders SCENE without the legend to OUT_PNG; CHECK (atmoglobe_image_check)
# must find no pixel that differs.
foreach(step VIEW RENDER CHECK)
  execute_process(COMMAND ${${step}} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${step}: exit ${rc}\n${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${step} failed")
  endif()
  if(step STREQUAL "VIEW" AND NOT out MATCHES "scene saved: ")
    message(FATAL_ERROR "the viewer did not say it saved the scene")
  endif()
endforeach()
