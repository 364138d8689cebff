# Renders K independent batches (seeds 1..K) of a test scene and of a reference scene with the same settings,
# requires zero non-finite samples in each, then fh_compare --same-distribution (per-pixel Welch t test,
# Bonferroni-corrected; tests/render/image_compare.h).
#
#   cmake -DFREDHOLM=exe -DCOMPARE=exe -DOUT=dir -DNAME=name -DBATCHES=K -DRENDER="args"
#         (-DREFERENCE_SCENE=file | -DTEST_SCENE=file -DREFERENCE_NAME=name [-DTEST_EXTRA="args"]) -P run_batch_test.cmake
#
# The reference batches are the same renders for every test that shares a reference scene and RENDER, so they are
# rendered once: with REFERENCE_SCENE the script only renders them, named after NAME (a ctest fixture); with
# TEST_SCENE it renders the test batches and compares them with those the fixture named REFERENCE_NAME rendered.
cmake_minimum_required(VERSION 3.25)
file(MAKE_DIRECTORY ${OUT})
separate_arguments(render_args UNIX_COMMAND "${RENDER}")
separate_arguments(test_extra UNIX_COMMAND "${TEST_EXTRA}")

# The images of batches 1..K named `prefix`, comma-separated.
function(list_batches prefix out_list)
  set(images "")
  foreach(seed RANGE 1 ${BATCHES})
    list(APPEND images ${OUT}/${prefix}_${seed}.exr)
  endforeach()
  list(JOIN images "," joined)
  set(${out_list} "${joined}" PARENT_SCOPE)
endfunction()

function(render_batches scene prefix extra)
  foreach(seed RANGE 1 ${BATCHES})
    set(image ${OUT}/${prefix}_${seed}.exr)
    set(stats ${OUT}/${prefix}_${seed}.json)
    set(command ${FREDHOLM} render ${scene} ${render_args} ${extra} --seed ${seed} -o ${image} --stats ${stats} --quiet)
    execute_process(COMMAND ${command} RESULT_VARIABLE rc ERROR_VARIABLE err)
    list(JOIN command " " printable)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${NAME}: fredholm exited with ${rc}: ${err}\n  reproduce: ${printable}")
    endif()
    file(READ ${stats} json)
    string(JSON nonfinite GET "${json}" nonfinite_samples)
    if(NOT nonfinite EQUAL 0)
      message(FATAL_ERROR "${NAME}: ${nonfinite} non-finite samples\n  reproduce: ${printable}")
    endif()
  endforeach()
endfunction()

if(DEFINED REFERENCE_SCENE)
  render_batches(${REFERENCE_SCENE} ${NAME}_reference "")
  message(STATUS "${NAME}: rendered ${BATCHES} reference batches")
  return()
endif()
render_batches(${TEST_SCENE} ${NAME}_test "${test_extra}")
list_batches(${NAME}_test test_images)
list_batches(${REFERENCE_NAME}_reference reference_images)
string(REPLACE "," ";" references "${reference_images}")
foreach(image IN LISTS references)
  if(NOT EXISTS ${image})
    message(FATAL_ERROR "${NAME}: no reference batch ${image} (rendered by the fixture named ${REFERENCE_NAME})")
  endif()
endforeach()
execute_process(COMMAND ${COMPARE} ${test_images} --same-distribution ${reference_images}
                        --diff-out ${OUT}/${NAME}.diff.exr RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NAME}: the test scene's pixels differ in distribution from the reference's (images in ${OUT})")
endif()
message(STATUS "${NAME}: passed")
