# atmoglobe_embed_files(<target> FUNCTION <cxx-function-name> FILES <files...>)
# Generates a source file holding the bytes of <files> and a lookup function
#   std::optional<std::string_view> <function>(std::string_view fileName)
# (declared by the caller), and adds it to <target>. The files are embedded at build
# time, so the binary needs nothing from the source tree at run time.
set(_ATMOGLOBE_EMBED_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/EmbedFilesScript.cmake")
function(atmoglobe_embed_files target)
  cmake_parse_arguments(ARG "" "FUNCTION;NAMESPACE" "FILES" ${ARGN})
  set(out "${CMAKE_CURRENT_BINARY_DIR}/${ARG_FUNCTION}_embedded.cpp")
  add_custom_command(
    OUTPUT "${out}"
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DFUNCTION=${ARG_FUNCTION} -DNAMESPACE=${ARG_NAMESPACE}
            "-DFILES=${ARG_FILES}" -P "${_ATMOGLOBE_EMBED_SCRIPT}"
    DEPENDS ${ARG_FILES} "${_ATMOGLOBE_EMBED_SCRIPT}"
    COMMENT "Embedding ${ARG_FUNCTION}: ${ARG_FILES}"
    VERBATIM)
  target_sources(${target} PRIVATE "${out}")
endfunction()
