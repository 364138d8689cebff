# Runs a `fredholm` command line that is bad usage and requires: exit code 2, exactly one line on stderr that matches
# EXPECT (it names the option and what it takes), nothing on stdout.
#
#   cmake -DFREDHOLM=exe "-DARGS=render scene.gltf -o out.exr --nee maybe" -DEXPECT=regex -P run_usage_error.cmake
cmake_minimum_required(VERSION 3.25)
separate_arguments(args UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${FREDHOLM} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(problems "")
include(${CMAKE_CURRENT_LIST_DIR}/one_line_failure.cmake)
check_one_line_failure(problems "${rc}" 2 "${out}" "${err}" "${EXPECT}")
if(problems)
  message(FATAL_ERROR "fredholm ${ARGS}: ${problems}stderr: ${err}")
endif()
