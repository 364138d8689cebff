# Runs one viewer test. Modes: compare, script (both need xvfb-run; without it they are reported as skipped), and
# nodisplay.
#   cmake -DFREDHOLM=exe -DCOMPARE=exe -DOUT=dir -DSCENE=file -DMODE=mode [-DXVFB_RUN=exe] -P run_viewer_test.cmake
cmake_minimum_required(VERSION 3.25)
file(MAKE_DIRECTORY ${OUT})

function(run_checked)  # run_checked(EXPECT rc COMMAND ...): runs, requires the exit code, prints the command on failure
  cmake_parse_arguments(R "" "EXPECT" "COMMAND" ${ARGN})
  list(JOIN R_COMMAND " " printable)
  execute_process(COMMAND ${R_COMMAND} RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out)
  message(STATUS "${printable}\n${out}${err}")
  if(NOT rc STREQUAL R_EXPECT)
    message(FATAL_ERROR "${MODE}: exit code ${rc}, expected ${R_EXPECT}\n  reproduce: ${printable}")
  endif()
  set(stderr_text "${err}" PARENT_SCOPE)
  set(stdout_text "${out}" PARENT_SCOPE)
  set(printable "${printable}" PARENT_SCOPE)
endfunction()

if(MODE STREQUAL "nodisplay")
  run_checked(EXPECT 1 COMMAND ${CMAKE_COMMAND} -E env --unset=DISPLAY --unset=WAYLAND_DISPLAY
              ${FREDHOLM} view ${SCENE} --frames 2)
  string(STRIP "${stderr_text}" text)
  string(FIND "${text}" "\n" newline)
  if(NOT newline EQUAL -1 OR NOT text MATCHES "fredholm render")
    message(FATAL_ERROR "nodisplay: expected one error line naming `fredholm render`, got:\n${stderr_text}")
  endif()
  message(STATUS "nodisplay: passed")
  return()
endif()

if(NOT XVFB_RUN)
  message(STATUS "viewer tests skipped: xvfb-run not found (Debian package xvfb)")
  message(FATAL_ERROR "SKIPPED: xvfb-run not found")  # ctest reports the test as skipped (SKIP_REGULAR_EXPRESSION)
endif()
set(xvfb ${XVFB_RUN} -a -s "-screen 0 1024x768x24")

if(MODE STREQUAL "compare")
  set(shot ${OUT}/viewer_cornell.exr)
  set(ref ${OUT}/viewer_cornell_render.exr)
  run_checked(EXPECT 0 COMMAND ${xvfb} ${FREDHOLM} view ${SCENE} --width 128 --height 128 --frames 64
              --spp-per-frame 1 --screenshot ${shot})
  set(view_command "${printable}")
  run_checked(EXPECT 0 COMMAND ${FREDHOLM} render ${SCENE} --width 128 --height 128 --spp 64 -o ${ref} --quiet)
  foreach(check "--reference;${ref};--max-block-rel;0.25;--max-mean-rel;0.02" "--identical;${ref}")
    execute_process(COMMAND ${COMPARE} ${shot} ${check} RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "compare: fh_compare ${shot} ${check} failed; images kept in ${OUT}\n"
                          "  reproduce: ${view_command}\n  and: ${printable}")
    endif()
  endforeach()
elseif(MODE STREQUAL "script")
  set(shot ${OUT}/viewer_script.exr)
  run_checked(EXPECT 0 COMMAND ${CMAKE_COMMAND} -E env FREDHOLM_VALIDATION=1 ${xvfb} ${FREDHOLM} view ${SCENE}
              --width 128 --height 128 --frames 24 --script resize,orbit,zoom,pan,depth,nee,tonemap
              --screenshot ${shot})
  if(stderr_text MATCHES "validation" OR NOT stderr_text MATCHES " 0 non-finite samples")
    message(FATAL_ERROR "script: validation messages or non-finite samples\n  reproduce: ${printable}")
  endif()
  execute_process(COMMAND ${COMPARE} ${shot} --finite RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "script: non-finite pixels in ${shot}\n  reproduce: ${printable}")
  endif()
elseif(MODE STREQUAL "lens")
  # The viewer with a lens (options as render's) accumulates the same bits as `fredholm render` with that lens; then
  # F twice (f/16, f/8), a click at the centre to focus there, and C prints the lens with its focus distance.
  set(shot ${OUT}/viewer_lens.exr)
  set(ref ${OUT}/viewer_lens_render.exr)
  set(lens --aperture 2 --focus-on 40,90 --aperture-blades 6)
  run_checked(EXPECT 0 COMMAND ${xvfb} ${FREDHOLM} view ${SCENE} --width 128 --height 128 --frames 16
              --spp-per-frame 1 ${lens} --screenshot ${shot})
  set(view_command "${printable}")
  run_checked(EXPECT 0 COMMAND ${FREDHOLM} render ${SCENE} --width 128 --height 128 --spp 16 ${lens} -o ${ref} --quiet)
  execute_process(COMMAND ${COMPARE} ${shot} --identical ${ref} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "lens: the viewer's lens image differs from render's; images kept in ${OUT}\n"
                        "  reproduce: ${view_command}\n  and: ${printable}")
  endif()
  run_checked(EXPECT 0 COMMAND ${CMAKE_COMMAND} -E env FREDHOLM_VALIDATION=1 ${xvfb} ${FREDHOLM} view ${SCENE}
              --width 128 --height 128 --frames 20 --script aperture,aperture,focus,print --screenshot ${shot})
  if(stderr_text MATCHES "validation" OR NOT stderr_text MATCHES " 0 non-finite samples" OR
     NOT stdout_text MATCHES "--aperture 8 --focus-distance [0-9.]+")
    message(FATAL_ERROR "lens: validation messages, non-finite samples, or no lens in the printed command\n"
                        "  reproduce: ${printable}")
  endif()
elseif(MODE STREQUAL "target")
  # --target-error: the viewer estimates the film's error as it grows and stops adding samples once it is reached
  # (120 frames of 2 spp would be 240 spp; 5% is reached long before).
  run_checked(EXPECT 0 COMMAND ${xvfb} ${FREDHOLM} view ${SCENE} --width 128 --height 128 --frames 120
              --spp-per-frame 2 --target-error 0.05)
  if(NOT stderr_text MATCHES "target error 5% reached at ([0-9]+) spp")
    message(FATAL_ERROR "target: no line saying the target was reached\n  reproduce: ${printable}")
  endif()
  set(reached ${CMAKE_MATCH_1})
  if(NOT stderr_text MATCHES "128x128, ${reached} spp, .*estimated relative error [0-9.]+%" OR reached GREATER_EQUAL 240)
    message(FATAL_ERROR "target: kept rendering after the target (reached at ${reached} spp)\n  reproduce: ${printable}")
  endif()
else()
  message(FATAL_ERROR "unknown MODE ${MODE}")
endif()
message(STATUS "${MODE}: passed (images in ${OUT})")
