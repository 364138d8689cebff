# Runs one render test: renders with fredholm, requires exit code 0, zero non-finite samples (and, for closed
# scenes, zero escaped rays) from the --stats JSON, then runs each fh_compare check. On failure it keeps the
# images and prints the command that reproduces the render.
#
#   cmake -DFREDHOLM=exe -DCOMPARE=exe -DOUT=dir -DNAME=name -DRENDER="args;..." [-DRENDER2="args;..."]
#         [-DCHECKS="check args|check args"] [-DCLOSED=1] -P run_render_test.cmake
# RENDER and RENDER2 are space-separated strings. In RENDER2 and CHECKS, @OUT@ stands for the output folder. RENDER2, if given, renders NAME_b the same way.
cmake_minimum_required(VERSION 3.25)
file(MAKE_DIRECTORY ${OUT})
set(image ${OUT}/${NAME}.exr)

function(render_and_check arg_string image stats)
  separate_arguments(args UNIX_COMMAND "${arg_string}")
  set(command ${FREDHOLM} render ${args} -o ${image} --png ${image}.png --stats ${stats} --quiet)
  list(JOIN command " " printable)
  execute_process(COMMAND ${command} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NAME}: fredholm exited with ${rc}\n  reproduce: ${printable}")
  endif()
  file(READ ${stats} json)
  string(JSON nonfinite GET "${json}" nonfinite_samples)
  if(NOT nonfinite EQUAL 0)
    message(FATAL_ERROR "${NAME}: ${nonfinite} non-finite samples\n  reproduce: ${printable}")
  endif()
  if(CLOSED)
    string(JSON escaped GET "${json}" escaped_rays)
    if(NOT escaped EQUAL 0)
      message(FATAL_ERROR "${NAME}: ${escaped} rays escaped a closed scene\n  reproduce: ${printable}")
    endif()
  endif()
  set(last_command "${printable}" PARENT_SCOPE)
endfunction()

render_and_check("${RENDER}" ${image} ${OUT}/${NAME}.json)
set(reproduce "${last_command}")
if(DEFINED RENDER2)
  string(REPLACE "@OUT@" "${OUT}" RENDER2 "${RENDER2}")
  render_and_check("${RENDER2}" ${OUT}/${NAME}_b.exr ${OUT}/${NAME}_b.json)
  set(reproduce "${reproduce}\n  and: ${last_command}")
endif()

if(DEFINED CHECKS)
  string(REPLACE "@OUT@" "${OUT}" CHECKS "${CHECKS}")
  string(REPLACE "|" ";" check_list "${CHECKS}")
  foreach(check IN LISTS check_list)
    separate_arguments(check_args UNIX_COMMAND "${check}")
    execute_process(COMMAND ${COMPARE} ${image} ${check_args} RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${NAME}: check failed: fh_compare ${image} ${check}\n  images kept in ${OUT}\n"
                          "  reproduce: ${reproduce}")
    endif()
  endforeach()
endif()
message(STATUS "${NAME}: passed (images in ${OUT})")
