# One function configures every target: language standard, warnings, sanitizers.
# No -ffast-math anywhere: geodesy and volume maths rely on IEEE semantics.
function(atmoglobe_configure_target target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wconversion -Wno-sign-conversion)
  if(ATMOGLOBE_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(ATMOGLOBE_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()
