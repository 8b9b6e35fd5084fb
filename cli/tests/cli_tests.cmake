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
# A cycle the closure search missed in the file's order (seed 9) closes in the canonical order
# of the connects, which every design file is verified in: valid, and the step that completes
# the cycle there (the chain's middle, made from both rods at once) says so.
file(WRITE ${tmp}/taut.yaml "fabkit: hacks/1\nenvironment:\n  - {name: left, primitives: {rod: {type: rod, radius: 4, length: 300}}, frame: {pos: [-204.12948237350665, 0, 500], rot: [90, 0, 0]}}\n  - {name: right, primitives: {rod: {type: rod, radius: 4, length: 300}}, frame: {pos: [204.12948237350665, 0, 485.6738923753454], rot: [90, 0, 180]}}\nparts:\n  - {name: s1, part: DoubleHook}\n  - {name: s2, part: DoubleHook}\n  - {name: s3, part: DoubleHook}\n  - {name: s4, part: DoubleHook}\n  - {name: s5, part: DoubleHook}\n  - {name: s6, part: DoubleHook}\n  - {name: s7, part: DoubleHook}\n  - {name: s8, part: DoubleHook}\n  - {name: s9, part: DoubleHook}\n  - {name: s10, part: DoubleHook}\nconnections:\n  - {connect: [s10.hook2, right.rod], alignment: flip}\n  - connect: [s9.hook2, s10.hook1]\n  - connect: [s8.hook2, s9.hook1]\n  - connect: [s7.hook2, s8.hook1]\n  - connect: [s6.hook2, s7.hook1]\n  - connect: [s5.hook2, s6.hook1]\n  - connect: [s4.hook2, s5.hook1]\n  - connect: [s3.hook2, s4.hook1]\n  - connect: [s2.hook2, s3.hook1]\n  - connect: [s1.hook2, s2.hook1]\n  - connect: [s1.hook1, left.rod]\n")
expect_run(0 "connect s5.hook2, s6.hook1: ok, closes cycle right.rod – s10 –"
           check ${tmp}/taut.yaml --seed 9)
# 1: usage.
expect_run(1 "design" check)
expect_run(1 "" nonsense-command)
expect_run(1 "" check a.yaml --restarts 0)
# 2: unreadable or malformed input.
expect_run(2 "cannot read design file" check ${tmp}/does-not-exist.yaml)
file(WRITE ${tmp}/syntax.yaml "fabkit: hacks/1\nenvironment:\n  - {name: door, part: [\n")
expect_run(2 "syntax.yaml:4:1: error: YAML syntax error" check ${tmp}/syntax.yaml)
file(WRITE ${tmp}/unknown.yaml "fabkit: hacks/1\nenvironment:\n  - {name: e, part: CeilingHok}\n")
expect_run(2 "unknown.yaml:3:" check ${tmp}/unknown.yaml)
expect_run(2 "did you mean" check ${tmp}/unknown.yaml)
file(WRITE ${tmp}/nan.yaml "fabkit: hacks/1\nenvironment:\n  - {name: e, primitives: {rod: {type: rod, radius: .nan, length: 5}}}\n")
expect_run(2 "not a finite number" check ${tmp}/nan.yaml)
expect_run(2 "unknown part 'NoSuchPart'" parts NoSuchPart)
# 3: infeasible design.
file(WRITE ${tmp}/infeasible.yaml
"fabkit: hacks/1\nenvironment:\n  - {name: rods, part: LongTensionRod}\nparts:\n  - {name: s, part: DoubleHook}\nconnections:\n  - connect: [s.hook1, rods.rod]\n")
expect_run(3 "infeasible.yaml:7:5: error: s.hook1: hook opening 9.6 mm is smaller than rod radius 12.7 mm (rods.rod)"
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
# A chain whose hook hangs by the tip of the next: which connect, turned the other way round,
# makes it hold (the design with that change is solved too; hacks Physics tests check it holds).
expect_run(4 "chain_hung_by_a_tip.yaml:24) — it holds"
           solve ${SOURCE_DIR}/examples/failing/chain_hung_by_a_tip.yaml)
expect_run(4 "note: with s1.hook2 and s2.hook1 connected the other way round — alignment: flip on that connect"
           solve ${SOURCE_DIR}/examples/failing/chain_hung_by_a_tip.yaml)
expect_run(3 "hook opening 9.6 mm is smaller than rod radius 12.7 mm" solve ${tmp}/infeasible.yaml)
expect_run(2 "YAML syntax error" solve ${tmp}/syntax.yaml)
expect_run(0 "wrote ${tmp}/demo/result.json" demo -o ${tmp}/demo)

# serve: bad options are usage errors; a design that cannot be read is refused up front.
expect_run(1 "" serve --port 70000)
expect_run(2 "cannot read design file" serve ${tmp}/does-not-exist.yaml --port 0)

# The kit comes from the header: missing or unknown headers name the known kits.
file(WRITE ${tmp}/noheader.yaml "environment:\n  - {name: e, part: CeilingHook}\n")
expect_run(2 "noheader.yaml:1:1: error: the file has no 'fabkit:' header naming its kit; start it with one of: fabkit: hacks/1"
           check ${tmp}/noheader.yaml)
file(WRITE ${tmp}/badkit.yaml "fabkit: hackz/1\n")
expect_run(2 "unknown kit 'hackz/1' in the fabkit: header; did you mean 'hacks'?" check ${tmp}/badkit.yaml)
expect_run(2 "unknown kit" build ${tmp}/badkit.yaml -o ${tmp}/badkit)
# build: for hacks, what solve -o does.
expect_run(0 "verdict                     STABLE" build ${SOURCE_DIR}/examples/hacks/bird_feeder.yaml -o ${tmp}/built)
foreach(f result.json scene.glb preview.svg assembly.stl assembly.obj)
  if(NOT EXISTS ${tmp}/built/${f})
    message(FATAL_ERROR "fabkit build -o did not write ${f}")
  endif()
endforeach()
expect_run(1 "output" build ${SOURCE_DIR}/examples/hacks/bird_feeder.yaml)
expect_run(4 "falls apart" build ${SOURCE_DIR}/examples/failing/hook_on_tilted_rod.yaml -o ${tmp}/tilted)
# 5: an output that cannot be written (a file where the directory should be).
file(WRITE ${tmp}/in_the_way "x")
expect_run(5 "cannot create output directory" build ${SOURCE_DIR}/examples/hacks/bird_feeder.yaml -o ${tmp}/in_the_way)
# Special files are refused, not read: a directory, a device that never ends.
expect_run(2 "it is a directory" check ${SOURCE_DIR}/examples)
if(EXISTS /dev/zero)
  expect_run(2 "not a regular file" check /dev/zero)
  expect_run(2 "not a regular file" serve /dev/zero --port 0)
endif()
expect_run(2 "cannot read part file" check ${SOURCE_DIR}/examples/hacks/bird_feeder.yaml --parts ${SOURCE_DIR}/examples)
# User part files reach `parts` and `serve` too, not only check and solve.
expect_run(0 "WallBracket" parts WallBracket --parts ${SOURCE_DIR}/examples/parts/wall_bracket.yaml)
expect_run(2 "cannot read part file" parts --parts ${tmp}/does-not-exist.yaml)
expect_run(2 "cannot read part file" serve --parts ${tmp}/does-not-exist.yaml --port 0)
