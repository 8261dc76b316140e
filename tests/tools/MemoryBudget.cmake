# The memory budget over a long time series (docs/memory.md).
# A SYNTHETIC grid of 100 hourly steps is rendered step by step twice: with --memory-budget
# BUDGET_MIB, and with a budget above the series' size (what no budget does on a machine with the
# RAM). `render --time-series` prints one line of what it held:
#   memory: budget B MiB, steps held peak H MiB (...); RSS before the series R0 MiB, after its
#   first frame R1 MiB, peak RSS P MiB
# Passes when, with the budget:
#   - the cache's own accounting held at most the budget (H <= B), and
#   - the process' peak RSS (getrusage ru_maxrss) grew over the series by at most the budget plus a
#     fixed OVERHEAD_MIB (P - R0 <= B + OVERHEAD): the shaders compiled at the first frame (llvmpipe's
#     JIT: R1 - R0, ~17 MiB measured), one step's staging and read buffers while it is loaded
#     (~5 MiB here), allocator slack;
# and, without it, the same series grew past that bound (so the test can fail: the budget is what
# keeps the first run under it). Both figures are printed.
# Inputs: CMD (atmoglobe), OUT (a directory), BUDGET_MIB, OVERHEAD_MIB, RSS_CHECK (OFF: only the
# cache's accounting, for sanitized builds).
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${CMD} synth --grid --grid-size 100,100,20,100 -o ${OUT}/series100.nc
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "synth failed: ${err}")
endif()

function(run_series budget prefix)
  execute_process(COMMAND ${CMD} render --grid ${OUT}/series100.nc --time-series --grid-step 2000 --no-map
                          --camera 34.4,-97.6,8e5,0,-60,0 --size 48x27 --memory-budget ${budget}
                          -o ${OUT}/${prefix}/s.png
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(REGEX MATCH "memory: budget ([0-9]+) MiB, steps held peak ([0-9]+) MiB[^;]*; RSS before the series ([0-9]+) MiB, after its first frame ([0-9]+) MiB, peak RSS ([0-9]+) MiB" line "${err}")
  if(NOT rc EQUAL 0 OR NOT line)
    message(FATAL_ERROR "render --memory-budget ${budget} failed (exit ${rc}) or printed no memory line:\n${err}")
  endif()
  message("--memory-budget ${budget}: ${line}")
  set(${prefix}_held ${CMAKE_MATCH_2} PARENT_SCOPE)
  set(${prefix}_before ${CMAKE_MATCH_3} PARENT_SCOPE)
  set(${prefix}_peak ${CMAKE_MATCH_5} PARENT_SCOPE)
endfunction()

run_series(${BUDGET_MIB} budgeted)
run_series(100000 unbudgeted)
math(EXPR bound "${BUDGET_MIB} + ${OVERHEAD_MIB}")
math(EXPR budgeted_growth "${budgeted_peak} - ${budgeted_before}")
math(EXPR unbudgeted_growth "${unbudgeted_peak} - ${unbudgeted_before}")
message("RSS growth over the series: ${budgeted_growth} MiB with a ${BUDGET_MIB} MiB budget, "
        "${unbudgeted_growth} MiB without (bound: budget + ${OVERHEAD_MIB} MiB overhead = ${bound} MiB); "
        "steps held peak ${budgeted_held} vs ${unbudgeted_held} MiB")
if(budgeted_held GREATER BUDGET_MIB)
  message(FATAL_ERROR "the cache held ${budgeted_held} MiB, over the ${BUDGET_MIB} MiB budget")
endif()
if(NOT unbudgeted_held GREATER BUDGET_MIB)
  message(FATAL_ERROR "without a budget the cache held only ${unbudgeted_held} MiB: the test does not show the budget at work")
endif()
if(DEFINED RSS_CHECK AND NOT RSS_CHECK)
  message("RSS not checked (RSS_CHECK=OFF: a sanitized build, whose RSS holds ASan's quarantine)")
  return()
endif()
if(budgeted_growth GREATER bound)
  message(FATAL_ERROR "peak RSS grew ${budgeted_growth} MiB over the series, over budget + overhead = ${bound} MiB")
endif()
if(NOT unbudgeted_growth GREATER bound)
  message(FATAL_ERROR "without a budget the series grew only ${unbudgeted_growth} MiB: the test does not show the budget at work")
endif()
