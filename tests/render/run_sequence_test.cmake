# A frame sequence: `fredholm render SCENE --frames 0:2 --fps 2 -o seq_##.exr` writes seq_00, seq_01 and seq_02, each
# posed at frame / fps; frame 1 has the bits of a single render at --time 0.5, and an interrupted-free run exits 0.
#   cmake -DFREDHOLM=exe -DCOMPARE=exe -DOUT=dir -DSCENE=file -P run_sequence_test.cmake
cmake_minimum_required(VERSION 3.25)
set(dir ${OUT}/sequence)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
set(common --width 32 --height 32 --spp 4 --quiet)
set(images "${dir}/seq_##.exr")  # quoted: # starts a comment in CMake
set(stats "${dir}/seq_##.json")
execute_process(COMMAND ${FREDHOLM} render ${SCENE} --frames 0:2 --fps 2 -o ${images} --stats ${stats} ${common}
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sequence: exit ${rc}\n${err}")
endif()
foreach(frame 00 01 02)
  if(NOT EXISTS ${dir}/seq_${frame}.exr OR NOT EXISTS ${dir}/seq_${frame}.json)
    message(FATAL_ERROR "sequence: frame ${frame} was not written")
  endif()
endforeach()
file(READ ${dir}/seq_02.json json)
string(JSON time GET "${json}" time)
if(NOT time EQUAL 1)
  message(FATAL_ERROR "sequence: frame 2 at 2 fps is posed at ${time} s, not 1 s")
endif()
execute_process(COMMAND ${FREDHOLM} render ${SCENE} --time 0.5 -o ${dir}/single.exr ${common} RESULT_VARIABLE rc)
execute_process(COMMAND ${COMPARE} ${dir}/seq_01.exr --identical ${dir}/single.exr RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sequence: frame 1 differs from a render at --time 0.5 (images in ${dir})")
endif()
# A pattern without # is one clear usage error, before anything renders.
execute_process(COMMAND ${FREDHOLM} render ${SCENE} --frames 0:1 -o ${dir}/plain.exr ${common}
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "no # for the frame number" OR EXISTS ${dir}/plain.exr)
  message(FATAL_ERROR "sequence: -o without # was not refused cleanly (exit ${rc}): ${err}")
endif()
message(STATUS "sequence: passed")
