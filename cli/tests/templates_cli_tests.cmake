# End-to-end checks of the templates kit on the command line: exit codes, what it prints and
# the files build writes. Run by ctest as: cmake -DFABKIT=<binary> -DSOURCE_DIR=<repo> [-DNODE=<node>] -P ...

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

set(tmp ${CMAKE_CURRENT_BINARY_DIR}/templates_cli_test_files)
file(REMOVE_RECURSE ${tmp})
file(MAKE_DIRECTORY ${tmp})
set(ex ${SOURCE_DIR}/examples/templates)

# Browsing the database.
expect_run(0 "12 source designs" templates list)
expect_run(0 "dining_table       Dining table" templates list)
expect_run(0 "leg_fl [LUM-PINE-4x4] 89 x 89 x 732 mm" templates show dining_table)
expect_run(0 "bottom_shelf [PLY-BIRCH-18]" templates show bookshelf/shelves)
expect_run(2 "did you mean 'dining_table'?" templates show dinning_table)
expect_run(1 "" templates)

# check: composition steps, stability, price; exit codes per failure class.
expect_run(0 "connected 4 of 4 linked pairs (LBR-40 + SCR-3.5x16 from coffee_table)" check ${ex}/table_with_shelf.yaml)
expect_run(0 "Dining table with a bottom shelf: feasible — 74 parts" check ${ex}/table_with_shelf.yaml)
expect_run(0 "Cabinet on wheels: feasible" check ${ex}/cabinet_on_wheels.yaml)
expect_run(0 "Garden bench with a backrest: feasible" check ${ex}/bench_with_backrest.yaml)
expect_run(2 "bad_model.yaml:5:60: error: unknown control 'size_q'; did you mean 'size_x'?" check ${ex}/bad_model.yaml)
file(WRITE ${tmp}/unknown.yaml "fabkit: templates/1\nmodel:\n  - {use: dinning_table}\n")
expect_run(2 "unknown.yaml:3:5: error: unknown template 'dinning_table'; did you mean 'dining_table'?" check ${tmp}/unknown.yaml)
file(WRITE ${tmp}/syntax.yaml "fabkit: templates/1\nmodel:\n  - {use: [\n")
expect_run(2 "syntax.yaml:4:1: error: YAML syntax error" check ${tmp}/syntax.yaml)
file(WRITE ${tmp}/neither.yaml "fabkit: templates/1\nname: x\n")
expect_run(2 "needs 'model:'" check ${tmp}/neither.yaml)
# 3: infeasible — a caster on a tabletop cannot be connected.
file(WRITE ${tmp}/caster.yaml "fabkit: templates/1\nmodel:\n  - {use: dining_table}\n  - {use: rolling_cart/wheels/caster_fl, at: [0, 0, 800], snap: false}\n")
expect_run(3 "no connection found between 'caster_fl' and 'top'" check ${tmp}/caster.yaml)
# 4: falls apart — the table without a leg, leaned on.
file(WRITE ${tmp}/three_legs.yaml "fabkit: templates/1\nmodel:\n  - {use: dining_table/top, as: top}\n  - {use: dining_table/base/legs/leg_fl, as: leg, snap: false, connect: false}\nloads:\n  - {part: top, at: [780, 430, 750], force: [0, 0, -200]}\n")
expect_run(4 "tips" check ${tmp}/three_legs.yaml)
# A source design is a model of itself.
expect_run(0 "feasible" check ${SOURCE_DIR}/templates/data/designs/coffee_table.yaml)

# build: every output.
expect_run(0 "built 'Dining table with a bottom shelf': 74 parts, $" build ${ex}/table_with_shelf.yaml -o ${tmp}/table)
foreach(f bom.csv bom.json report.html scene.glb stability.glb model.stl model.json preview.svg
          cuts_LUM-PINE-4x4.svg sheet_PLY-BIRCH-18_1.svg)
  if(NOT EXISTS ${tmp}/table/${f})
    message(FATAL_ERROR "fabkit build did not write ${f}")
  endif()
endforeach()
file(READ ${tmp}/table/bom.csv bom)
string(FIND "${bom}" "LBR-40,L-bracket 40 x 40 mm,4,1,pack" found)
if(found EQUAL -1)
  message(FATAL_ERROR "bom.csv lacks the four shelf brackets:\n${bom}")
endif()
file(READ ${tmp}/table/report.html report)
foreach(text "<h2>Bill of materials</h2>" "<h2>Cut diagrams</h2>" "<svg" "Every part is in static equilibrium")
  string(FIND "${report}" "${text}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "report.html lacks '${text}'")
  endif()
endforeach()
expect_run(1 "output" build ${ex}/table_with_shelf.yaml)
file(WRITE ${tmp}/in_the_way "x")
expect_run(5 "cannot create output directory" build ${ex}/table_with_shelf.yaml -o ${tmp}/in_the_way)
expect_run(2 "unknown control" build ${ex}/bad_model.yaml -o ${tmp}/bad)
if(EXISTS ${tmp}/bad/bom.csv)
  message(FATAL_ERROR "a model with errors must not write outputs")
endif()

# The scenes pass the Khronos glTF validator (when node and the validator are installed).
if(NODE AND EXISTS ${SOURCE_DIR}/tools/gltf-check/node_modules/gltf-validator)
  expect_run(0 "built" build ${ex}/cabinet_on_wheels.yaml -q -o ${tmp}/cabinet)
  execute_process(COMMAND ${NODE} ${SOURCE_DIR}/tools/gltf-check/check-glb.mjs
                          ${tmp}/table/scene.glb ${tmp}/table/stability.glb ${tmp}/cabinet/scene.glb
                  RESULT_VARIABLE code OUTPUT_VARIABLE text ERROR_VARIABLE text)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "the glTF validator rejected a templates scene:\n${text}")
  endif()
endif()
