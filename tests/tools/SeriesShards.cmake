# Shards of a time series (docs/scale-out.md): `render --time-series --shard K/N`, or a Slurm array
# task's SLURM_ARRAY_TASK_ID / _COUNT / _MIN set by hand as Slurm sets them, render disjoint runs
# of the series' frames, named as in the whole series; together they are the whole series, byte
# for byte. A SYNTHETIC grid of 4 steps with 2 frames per step: 7 frames.
# Inputs: CMD (atmoglobe), OUT (a directory). No Slurm daemons are started: this checks what each
# task does with the variables a real scheduler gives it.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${CMD} synth --grid --grid-size 30,30,8,4 -o ${OUT}/series.nc RESULT_VARIABLE rc
                OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "synth failed: ${err}")
endif()
set(common render --grid ${OUT}/series.nc --time-series --time-substeps 2 --grid-step 2000 --no-map
           --camera 34.4,-97.6,8e5,0,-60,0 --size 48x27)

# run(DIR EXPECTED_FRAMES [ENV VAR=VALUE...] [ARGS ...]): renders into OUT/DIR, checks the frames written.
function(run dir expected)
  cmake_parse_arguments(R "" "" "ENV;ARGS" ${ARGN})
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=SLURM_ARRAY_TASK_ID --unset=SLURM_ARRAY_TASK_COUNT
                          --unset=SLURM_ARRAY_TASK_MIN ${R_ENV} ${CMD} ${common} ${R_ARGS} -o ${OUT}/${dir}/s.png
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${dir}: exit ${rc}\n${out}\n${err}")
  endif()
  file(GLOB written RELATIVE ${OUT}/${dir} ${OUT}/${dir}/*.png)
  list(SORT written)
  if(NOT "${written}" STREQUAL "${expected}")
    message(FATAL_ERROR "${dir}: wrote [${written}], expected [${expected}]\n${err}")
  endif()
  message("${dir}: ${written}")
endfunction()

run(whole "s_000.png;s_001.png;s_002.png;s_003.png;s_004.png;s_005.png;s_006.png")
# Three shards, each into its own directory: floor(7k/3) = 0, 2, 4, 7.
run(shard0 "s_000.png;s_001.png" ARGS --shard 0/3)
# Task 5 of an array 4-6 (sbatch --array=4-6): shard 1 of 3.
run(shard1 "s_002.png;s_003.png" ENV SLURM_ARRAY_TASK_ID=5 SLURM_ARRAY_TASK_MIN=4 SLURM_ARRAY_TASK_COUNT=3)
# Task 2 of an array 0-2 (no MIN given: 0).
run(shard2 "s_004.png;s_005.png;s_006.png" ENV SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_COUNT=3)
foreach(pair "0;shard0" "1;shard0" "2;shard1" "3;shard1" "4;shard2" "5;shard2" "6;shard2")
  list(GET pair 0 i)
  list(GET pair 1 dir)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/whole/s_00${i}.png ${OUT}/${dir}/s_00${i}.png
                  RESULT_VARIABLE differ)
  if(NOT differ EQUAL 0)
    message(FATAL_ERROR "s_00${i}.png: the shard's frame differs from the whole series' frame")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/whole/s_000.png ${OUT}/whole/s_006.png
                RESULT_VARIABLE differ)
if(differ EQUAL 0)
  message(FATAL_ERROR "the first and last frames are the same picture: the series shows nothing that moves")
endif()
# More shards than frames: an empty shard writes nothing and succeeds.
run(empty "" ARGS --shard 0/8)
message("7 frames: 3 shards wrote each once, identical to the whole series")
