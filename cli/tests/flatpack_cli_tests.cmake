# End-to-end checks of `fabkit check` / `fabkit build` on flatpack designs.
function(expect_run expected_code expected_text)
  execute_process(COMMAND ${FABKIT} ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL expected_code)
    message(FATAL_ERROR "fabkit ${ARGN}: exit ${code}, expected ${expected_code}\n${out}\n${err}")
  endif()
  string(FIND "${out}${err}" "${expected_text}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "fabkit ${ARGN}: output lacks '${expected_text}'\n${out}\n${err}")
  endif()
endfunction()

set(tmp ${CMAKE_CURRENT_BINARY_DIR}/flatpack_cli_files)
file(REMOVE_RECURSE ${tmp})
file(MAKE_DIRECTORY ${tmp})
expect_run(0 "reading desk: valid — 11 components, 10 pieces, 17 joints (10 from connections, 7 automatic"
           check ${SOURCE_DIR}/examples/flatpack/reading_desk.yaml)
expect_run(0 "wrote ${tmp}/desk/sheet-1.svg" build ${SOURCE_DIR}/examples/flatpack/reading_desk.yaml -o ${tmp}/desk)
foreach(f sheet-1.dxf model.stl scene.glb report.json)
  if(NOT EXISTS ${tmp}/desk/${f})
    message(FATAL_ERROR "fabkit build did not write ${f}")
  endif()
endforeach()
file(WRITE ${tmp}/free.yaml "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 30}\n")
expect_run(2 "under-constrained: nothing determines A.w" check ${tmp}/free.yaml)
file(WRITE ${tmp}/typo.yaml "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 30, w: 3}\n  - {name: B, type: Rectangle, l: 30, w: 3}\nconnections:\n  - {connect: [A.tp, B.b]}\n")
expect_run(2 "A (Rectangle) has no edge 'tp'; did you mean 't'?" check ${tmp}/typo.yaml)
file(WRITE ${tmp}/cycle.yaml "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Square, l: 30}\n  - {name: B, type: Square, l: 30}\nconnections:\n  - {connect: [B.l, A.r]}\n  - {connect: [B.b, A.t]}\n")
expect_run(3 "disagrees with the placement" check ${tmp}/cycle.yaml)

# Every bundled example checks clean; the composites read their sub-designs next to them.
foreach(example bookend reading_desk stool computer_desk simple_table picnic_table box_stool
                bookshelf bed ladder bunk_bed cabinet tv_console box_with_lid)
  expect_run(0 ": valid —" check -q ${SOURCE_DIR}/examples/flatpack/${example}.yaml)
endforeach()
expect_run(0 "bunk bed: valid — 14 components, 14 pieces, 22 joints" check ${SOURCE_DIR}/examples/flatpack/bunk_bed.yaml)
expect_run(0 "meta-parameters: length = 300 (drives 1 dimension), width = 180 (drives 1 dimension), height = 150 (drives 4 dimensions), leg_width = 40 (drives 4 dimensions)"
           check ${SOURCE_DIR}/examples/flatpack/simple_table.yaml)
# The over-constrained picnic table: built with a failed check (exit 7), naming the pieces.
expect_run(7 "not assemblable: table.bench_front, table.bench_back, table.end_left, table.end_right lock each other"
           check ${SOURCE_DIR}/examples/flatpack/picnic_table_locked.yaml)
expect_run(7 "wrote ${tmp}/locked/report.json" build ${SOURCE_DIR}/examples/flatpack/picnic_table_locked.yaml -o ${tmp}/locked)
# A design that would contain itself.
file(WRITE ${tmp}/me.yaml "fabkit: flatpack/1\nuses: {Me: me.yaml}\ncomponents:\n  - {name: a, type: Me}\n")
expect_run(2 "me.yaml:2:12: error: component type Me (me.yaml) would contain itself: me.yaml uses me.yaml" check ${tmp}/me.yaml)

# The burn-test sheet: SVG and DXF, labelled cells, the widths printed.
expect_run(0 "burn test for plywood 3 mm: 25 cells" flatpack burn-test --thickness 3 --kerf 0.05:0.25:0.05
           --interference 0:0.2:0.05 -o ${tmp}/burn)
foreach(f burn-test.svg burn-test.dxf)
  if(NOT EXISTS ${tmp}/burn/${f})
    message(FATAL_ERROR "fabkit flatpack burn-test did not write ${f}")
  endif()
endforeach()
file(READ ${tmp}/burn/burn-test.svg svg)
foreach(needle "width=\"365mm\" height=\"210mm\" viewBox=\"0 0 365 210\"" "Δ 0.15 δ 0.05" "Δ 0.25 δ 0.2")
  string(FIND "${svg}" "${needle}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "burn-test.svg lacks '${needle}'")
  endif()
endforeach()
expect_run(0 "      0.1      0.05    9.225 mm  8.775 mm  2.750 mm" flatpack burn-test --kerf 0.1 --interference 0.05 -o ${tmp}/burn1)
expect_run(2 "--kerf: the range '0.2:0.1:0.05' needs start ≤ stop" flatpack burn-test --kerf 0.2:0.1:0.05 -o ${tmp}/burn2)
expect_run(2 "kerf 3 mm is outside 0 … 2 mm" flatpack burn-test --kerf 3 -o ${tmp}/burn2)
expect_run(1 "A subcommand is required" flatpack)
if(EXISTS ${tmp}/burn2)
  message(FATAL_ERROR "a refused burn test left ${tmp}/burn2 behind")
endif()

# The STL of every example is closed, one shell per piece, read by an independent tool: admesh
# finds as many parts as fabkit made pieces and has nothing to fix.
find_program(ADMESH admesh REQUIRED)
foreach(example bookend reading_desk stool computer_desk simple_table picnic_table bookshelf
                bunk_bed tv_console box_with_lid)
  execute_process(COMMAND ${FABKIT} build ${SOURCE_DIR}/examples/flatpack/${example}.yaml -o ${tmp}/stl_${example}
                  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "fabkit build ${example}: exit ${code}\n${out}\n${err}")
  endif()
  string(REGEX MATCH "components, ([0-9]+) pieces" _ "${out}")
  set(pieces ${CMAKE_MATCH_1})
  execute_process(COMMAND ${ADMESH} ${tmp}/stl_${example}/model.stl OUTPUT_VARIABLE report RESULT_VARIABLE code)
  string(REGEX MATCH "Number of parts *: *([0-9]+)" _ "${report}")
  if(NOT code EQUAL 0 OR NOT CMAKE_MATCH_1 EQUAL pieces)
    message(FATAL_ERROR "${example}: admesh finds ${CMAKE_MATCH_1} parts in model.stl, fabkit made ${pieces} pieces\n${report}")
  endif()
  foreach(field "Degenerate facets" "Edges fixed" "Facets removed" "Facets added" "Facets reversed" "Backwards edges")
    string(REGEX MATCH "${field} *: *([0-9]+)" _ "${report}")
    if(NOT CMAKE_MATCH_1 EQUAL 0)
      message(FATAL_ERROR "${example}: admesh reports ${field}: ${CMAKE_MATCH_1} in model.stl\n${report}")
    endif()
  endforeach()
endforeach()
