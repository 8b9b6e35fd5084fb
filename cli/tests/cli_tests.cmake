# End-to-end checks of the fabkit command line: exit codes and what it prints.
# Run by ctest as: cmake -DFABKIT=<binary> -DSOURCE_DIR=<repo> -P cli_tests.cmake

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

set(tmp ${CMAKE_CURRENT_BINARY_DIR}/cli_test_files)
file(MAKE_DIRECTORY ${tmp})

# 0: valid.
expect_run(0 "basket between rods: valid" check ${SOURCE_DIR}/examples/hacks/basket_between_rods.yaml)
expect_run(0 "closes cycle rods.rod2 – eyehook2 – basket – eyehook1 – rods.rod1"
           check ${SOURCE_DIR}/examples/hacks/basket_between_rods.yaml)
expect_run(0 "verdict                     STABLE" demo -o ${tmp}/demo0)
expect_run(0 "DoubleHook" parts)
expect_run(0 "hook1        hook (arc angle 270°" parts DoubleHook)
# 1: usage.
expect_run(1 "design" check)
expect_run(1 "" nonsense-command)
expect_run(1 "" check a.yaml --restarts 0)
# 2: unreadable or malformed input.
expect_run(2 "cannot open design file" check ${tmp}/does-not-exist.yaml)
file(WRITE ${tmp}/syntax.yaml "environment:\n  - {name: door, part: [\n")
expect_run(2 "syntax.yaml:3:1: error: YAML syntax error" check ${tmp}/syntax.yaml)
file(WRITE ${tmp}/unknown.yaml "environment:\n  - {name: e, part: CeilingHok}\n")
expect_run(2 "unknown.yaml:2:" check ${tmp}/unknown.yaml)
expect_run(2 "did you mean" check ${tmp}/unknown.yaml)
file(WRITE ${tmp}/nan.yaml "environment:\n  - {name: e, primitives: {rod: {type: rod, radius: .nan, length: 5}}}\n")
expect_run(2 "not a finite number" check ${tmp}/nan.yaml)
expect_run(2 "unknown part 'NoSuchPart'" parts NoSuchPart)
# 3: infeasible design.
file(WRITE ${tmp}/infeasible.yaml
"environment:\n  - {name: rods, part: LongTensionRod}\nparts:\n  - {name: s, part: DoubleHook}\nconnections:\n  - connect: [s.hook1, rods.rod]\n")
expect_run(3 "infeasible.yaml:6:5: error: s.hook1: hook opening 11.6 mm is smaller than rod radius 12.7 mm (rods.rod)"
           check ${tmp}/infeasible.yaml)

# solve: 0 stable (and the outputs), 4 falls apart, 3 infeasible, 2 bad input.
expect_run(0 "verdict                     STABLE" solve ${SOURCE_DIR}/examples/hacks/bird_feeder.yaml -o ${tmp}/bird)
foreach(f result.json scene.glb assembly.stl assembly.obj)
  if(NOT EXISTS ${tmp}/bird/${f})
    message(FATAL_ERROR "fabkit solve -o did not write ${f}")
  endif()
endforeach()
expect_run(4 "falls apart: shook.hook1 slides off the open end of bar.rod (t = 0)"
           solve ${SOURCE_DIR}/examples/failing/hook_on_tilted_rod.yaml)
expect_run(3 "hook opening 11.6 mm is smaller than rod radius 12.7 mm" solve ${tmp}/infeasible.yaml)
expect_run(2 "YAML syntax error" solve ${tmp}/syntax.yaml)
expect_run(0 "wrote ${tmp}/demo/result.json" demo -o ${tmp}/demo)

# serve: bad options are usage errors; a design that cannot be read is refused up front.
expect_run(1 "" serve --port 70000)
expect_run(2 "cannot open design file" serve ${tmp}/does-not-exist.yaml --port 0)
