# Runs `fredholm render` that must fail (a malformed scene, a film too large) and requires: exit code 1,
# exactly one line on stderr that names the scene file and matches EXPECT, nothing on stdout, and no output
# image (nor temporary file).
#
#   cmake -DFREDHOLM=exe -DSCENE=file -DNAME=name -DOUT=dir [-DARGS="--width 4096 ..."] -DEXPECT=regex
#         -P run_failing_render.cmake
cmake_minimum_required(VERSION 3.25)
set(dir ${OUT}/${NAME})
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
set(image ${dir}/out.exr)
if(NOT ARGS)
  set(ARGS "--width 8 --height 8 --spp 1")
endif()
separate_arguments(args UNIX_COMMAND "${ARGS}")
set(command ${FREDHOLM} render ${SCENE} -o ${image} ${args})
execute_process(COMMAND ${command} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
list(JOIN command " " printable)
set(problems "")
include(${CMAKE_CURRENT_LIST_DIR}/one_line_failure.cmake)
check_one_line_failure(problems "${rc}" 1 "${out}" "${err}" "${EXPECT}")
get_filename_component(file_name ${SCENE} NAME)
string(FIND "${err}" "${file_name}: " at)
if(at EQUAL -1)
  string(APPEND problems "stderr does not name ${file_name}; ")
endif()
file(GLOB left ${dir}/* ${dir}/.*)
if(left)
  string(APPEND problems "files left behind: ${left}; ")
endif()
if(problems)
  message(FATAL_ERROR "${NAME}: ${problems}\n  stderr: ${err}\n  reproduce: ${printable}")
endif()
