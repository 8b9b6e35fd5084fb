# The fabkit launcher (cli/src/launcher.cpp) starts fabkit-hacks for hacks commands and
# fabkit-all for everything else: checked by what the started process loads (glibc's
# LD_DEBUG=files names every library and who needs it), and by the answers being the same.
# Run by ctest as: cmake -DFABKIT=<launcher> -DSOURCE_DIR=<repo> -P launcher_tests.cmake

function(expect_program expected_program expected_code)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env LD_DEBUG=files ${FABKIT} ${ARGN} TIMEOUT 120
                  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL expected_code)
    message(FATAL_ERROR "fabkit ${ARGN}: exit ${code}, expected ${expected_code}\n${out}\n${err}")
  endif()
  # The started program keeps the launcher's name, so it is told by what it loads: both load
  # the hacks kit's libraries (yaml-cpp), only fabkit-all the other kits' (lib3MF, OpenSSL,
  # IPOPT, SQLite).
  string(FIND "${err}" "file=libyaml-cpp" kit_program)
  if(kit_program EQUAL -1)
    message(FATAL_ERROR "fabkit ${ARGN}: no kit program ran\n${err}")
  endif()
  foreach(lib lib3MF libssl libipopt libsqlite3)
    string(FIND "${err}" "file=${lib}" loaded)
    if(expected_program STREQUAL "fabkit-hacks" AND NOT loaded EQUAL -1)
      message(FATAL_ERROR "fabkit ${ARGN}: loaded ${lib}: fabkit-all ran, not fabkit-hacks")
    endif()
    if(expected_program STREQUAL "fabkit-all" AND loaded EQUAL -1)
      message(FATAL_ERROR "fabkit ${ARGN}: did not load ${lib}: fabkit-all did not run")
    endif()
  endforeach()
endfunction()

set(ex ${SOURCE_DIR}/examples)
set(tmp ${CMAKE_CURRENT_BINARY_DIR}/launcher_files)
file(REMOVE_RECURSE ${tmp})
file(MAKE_DIRECTORY ${tmp})

expect_program(fabkit-hacks 0 solve ${ex}/hacks/charger_holder.yaml -q)
expect_program(fabkit-hacks 0 check ${ex}/hacks/charger_holder.yaml)
expect_program(fabkit-hacks 0 build ${ex}/hacks/charger_holder.yaml -o ${tmp}/out)
expect_program(fabkit-hacks 0 parts Mug)
# A part file without a header does not change the kit; a file of another kit does.
expect_program(fabkit-hacks 0 check ${ex}/hacks/charger_holder.yaml --parts ${ex}/parts/wall_bracket.yaml)
expect_program(fabkit-all 2 check ${ex}/hacks/charger_holder.yaml --parts ${ex}/rods/guitar_stand.yaml)
expect_program(fabkit-all 0 check ${ex}/rods/guitar_stand.yaml)
expect_program(fabkit-all 0 --version)
# No readable design: fabkit-all says what is wrong, as before.
expect_program(fabkit-all 2 solve ${tmp}/missing.yaml)
expect_program(fabkit-all 1 check)
