# End-to-end checks of `fabkit check` / `fabkit build` for rods/1 designs: exit codes, what
# they print, the files they write, and those files judged by independent tools (admesh for
# the joint STLs, the Khronos glTF validator for the scene).
# Run by ctest as: cmake -DFABKIT=<binary> -DSOURCE_DIR=<repo> [-DNODE=<node>] [-DADMESH=<admesh>]
#                        -P rods_cli_tests.cmake

function(expect_run expected_code expected_text)
  execute_process(COMMAND ${FABKIT} ${ARGN}
                  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL expected_code)
    message(FATAL_ERROR "fabkit ${ARGN}: exit ${code}, expected ${expected_code}\n${out}\n${err}")
  endif()
  string(FIND "${out}${err}" "${expected_text}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "fabkit ${ARGN}: output lacks '${expected_text}'\n${out}\n${err}")
  endif()
endfunction()

set(ex ${SOURCE_DIR}/examples/rods)
set(tmp ${CMAKE_CURRENT_BINARY_DIR}/rods_cli_test_files)
file(REMOVE_RECURSE ${tmp})
file(MAKE_DIRECTORY ${tmp})

# 0: every gallery design checks clean.
foreach(design guitar_stand coffee_table lamp_1400 lamp_700 bowl_square stool twisted_prism geodesic_dome wolf_head_52)
  expect_run(0 "every check passed" check ${ex}/${design}.yaml)
endforeach()
expect_run(0 "cut plan: 5 stock rods of 914.4 mm, proven optimal" check ${ex}/guitar_stand.yaml)
expect_run(0 "closest rods: rod 02-05 and rod 03-06 pass 1.06 mm apart" check ${ex}/twisted_prism.yaml)
expect_run(0 "12 of 12 joints are the same as printed for" check ${ex}/lamp_700.yaml)

# 7: built (checked), but a check failed; each failing design names its finding.
expect_run(7 "rods_intersect.yaml:22:5: error: rod 03-04 and rod 05-06 intersect" check ${ex}/failing/rods_intersect.yaml)
expect_run(7 "joints 02 and 03 overlap and swallow the rod" check ${ex}/failing/joint_swallows_rod.yaml)
expect_run(7 "rod 02-03 is 21.73 mm long, shorter than the minimum rod length 30 mm" check ${ex}/failing/rod_too_short.yaml)
expect_run(7 "unbalanced: the centre of mass" check ${ex}/failing/unbalanced.yaml)
expect_run(7 "rod 01-04 buckles" check ${ex}/failing/overstressed.yaml)
# 3: cannot be built: a rod longer than the stock (named, with both lengths).
expect_run(3 "piece 'rod 01-04' is 1140.627 mm long, longer than the usable stock length 894.4 mm" check ${ex}/failing/rod_longer_than_stock.yaml)
expect_run(3 "nothing written" build ${ex}/failing/rod_longer_than_stock.yaml -o ${tmp}/none)
if(EXISTS ${tmp}/none/report.json)
  message(FATAL_ERROR "an infeasible build wrote outputs")
endif()

# 2: unreadable input, with file:line.
file(WRITE ${tmp}/nan.yaml "fabkit: rods/1\nname: nan\nrod: {radius: .nan}\nnodes:\n  - [0, 0, 0]\n  - [100, 0, 0]\nedges:\n  - [1, 2]\n")
expect_run(2 "nan.yaml:3:15: error: rod radius is .nan, not a finite number" check ${tmp}/nan.yaml)
file(WRITE ${tmp}/loop.yaml "fabkit: rods/1\nname: loop\nnodes:\n  - [0, 0, 0]\n  - [100, 0, 0]\nedges:\n  - [1, 2]\n  - [2, 2]\n")
expect_run(2 "loop.yaml:8:5: error: edge 2 joins node 2 to itself" check ${tmp}/loop.yaml)
file(WRITE ${tmp}/dup.yaml "fabkit: rods/1\nname: dup\nnodes:\n  - [0, 0, 0]\n  - [100, 0, 0]\nedges:\n  - [1, 2]\n  - [2, 1]\n")
expect_run(2 "dup.yaml:8:5: error: edge 2 joins nodes 2 and 1 again" check ${tmp}/dup.yaml)
file(WRITE ${tmp}/lonely.yaml "fabkit: rods/1\nname: lonely\nnodes:\n  - [0, 0, 0]\n  - [100, 0, 0]\n  - [5, 5, 5]\nedges:\n  - [1, 2]\n")
expect_run(2 "lonely.yaml:6:5: error: node 3 at [5, 5, 5] is not joined" check ${tmp}/lonely.yaml)
file(WRITE ${tmp}/typo.yaml "fabkit: rods/1\nname: typo\nrod: {material: oack}\nnodes:\n  - [0, 0, 0]\n  - [100, 0, 0]\nedges:\n  - [1, 2]\n")
expect_run(2 "did you mean 'oak'?" check ${tmp}/typo.yaml)
file(WRITE ${tmp}/unknown_kit.yaml "fabkit: rodz/1\n")
expect_run(2 "rods/1" check ${tmp}/unknown_kit.yaml)

# build: the README's first command, then every file judged by independent tools.
expect_run(0 "wrote 12 files" build ${ex}/guitar_stand.yaml -o ${tmp}/guitar)
foreach(f joint_01.stl joint_06.stl joints.3mf scene.glb cut_plan.svg cut_list.csv assembly.json report.json)
  if(NOT EXISTS ${tmp}/guitar/${f})
    message(FATAL_ERROR "fabkit build did not write ${f}")
  endif()
endforeach()
file(READ ${tmp}/guitar/cut_list.csv csv)
string(REGEX MATCHALL "\nrod [0-9][0-9]-[0-9][0-9]," rows "\n${csv}")
list(LENGTH rows count)
if(NOT count EQUAL 8)
  message(FATAL_ERROR "cut_list.csv has ${count} rods, not 8:\n${csv}")
endif()
file(READ ${tmp}/guitar/assembly.json assembly)
string(FIND "${assembly}" "\"text\": \"place joint 01\"" first)
if(first EQUAL -1)
  message(FATAL_ERROR "assembly.json does not start at joint 01:\n${assembly}")
endif()
if(ADMESH)
  foreach(i 1 2 3 4 5 6)
    execute_process(COMMAND ${ADMESH} ${tmp}/guitar/joint_0${i}.stl OUTPUT_VARIABLE report ERROR_VARIABLE report)
    foreach(line "Number of parts       :     1" "Edges fixed           :     0" "Backwards edges       :     0"
                 "Degenerate facets     :     0" "Facets removed        :     0" "Facets added          :     0")
      string(FIND "${report}" "${line}" found)
      if(found EQUAL -1)
        message(FATAL_ERROR "admesh does not call joint_0${i}.stl watertight ('${line}' missing):\n${report}")
      endif()
    endforeach()
  endforeach()
endif()
if(NODE AND EXISTS ${SOURCE_DIR}/tools/gltf-check/node_modules/gltf-validator)
  execute_process(COMMAND ${NODE} ${SOURCE_DIR}/tools/gltf-check/check-glb.mjs ${tmp}/guitar/scene.glb
                  RESULT_VARIABLE code OUTPUT_VARIABLE text ERROR_VARIABLE text)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "the glTF validator rejected the rods scene:\n${text}")
  endif()
endif()

# build with failed checks: still written, exit 7.
expect_run(7 "built, but 1 check failed" build ${ex}/failing/rods_intersect.yaml -o ${tmp}/crossing)
if(NOT EXISTS ${tmp}/crossing/report.json)
  message(FATAL_ERROR "a build with findings wrote no report")
endif()
# 5: the output directory cannot be made (a file is in the way).
file(WRITE ${tmp}/blocker "not a directory")
expect_run(5 "" build ${ex}/twisted_prism.yaml -o ${tmp}/blocker/out)
# 6: stopped at the time limit.
expect_run(6 "stopped at the deadline" build ${ex}/geodesic_dome.yaml -o ${tmp}/dome --time-limit 0.001)
