# The command line against special files, hostile bytes and time limits, for every kit
# (issue 10): input must be a regular file under the size cap, outputs never replace a FIFO,
# a device or a link out of their directory, invalid UTF-8 gets a clear error, and
# --time-limit stops check, solve and build with exit 6 and "stopped at the deadline".
# Run by ctest as: cmake -DFABKIT=<binary> -DSOURCE_DIR=<repo> -P security_cli_tests.cmake

function(expect_run expected_code expected_text)
  execute_process(COMMAND ${FABKIT} ${ARGN} TIMEOUT 120
                  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL expected_code)
    message(FATAL_ERROR "fabkit ${ARGN}: exit ${code}, expected ${expected_code}\n${out}\n${err}")
  endif()
  string(FIND "${out}${err}" "${expected_text}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "fabkit ${ARGN}: output lacks '${expected_text}'\n${out}\n${err}")
  endif()
  string(LENGTH "${out}${err}" length)
  if(length GREATER 200000)
    message(FATAL_ERROR "fabkit ${ARGN}: ${length} bytes of output")
  endif()
endfunction()

set(ex ${SOURCE_DIR}/examples)
set(tmp ${CMAKE_CURRENT_BINARY_DIR}/security_cli_files)
file(REMOVE_RECURSE ${tmp})
file(MAKE_DIRECTORY ${tmp})

# ---- inputs: special files are refused before any read (no hang on a FIFO) -----------------
execute_process(COMMAND mkfifo ${tmp}/design.yaml ${tmp}/parts.yaml)
expect_run(2 "not a regular file" check ${tmp}/design.yaml)
expect_run(2 "not a regular file" build ${tmp}/design.yaml -o ${tmp}/out)
expect_run(2 "not a regular file" solve ${tmp}/design.yaml)
expect_run(2 "cannot read part file" check ${ex}/hacks/bird_feeder.yaml --parts ${tmp}/parts.yaml)
expect_run(2 "no such file" check ${tmp}/missing.yaml)
# Larger than the 16 MiB cap (a sparse file: nothing is read).
file(WRITE ${tmp}/big.yaml "fabkit: hacks/1\n")
execute_process(COMMAND truncate -s 17M ${tmp}/big.yaml)
expect_run(2 "input files may be at most 16777216 bytes" check ${tmp}/big.yaml)
# A design naming part files that are a directory, a FIFO or missing: the line naming them.
file(WRITE ${tmp}/names_files.yaml "fabkit: hacks/1\npart_files: [parts.yaml, ., nope.yaml]\nenvironment:\n  - {name: r, part: LongTensionRod}\n")
expect_run(2 "names_files.yaml:2:14: error: cannot read part file" check ${tmp}/names_files.yaml)
expect_run(2 "it is a directory" check ${tmp}/names_files.yaml)
expect_run(2 "no such file" check ${tmp}/names_files.yaml)
# Empty files: an error with a line.
file(WRITE ${tmp}/empty.yaml "")
expect_run(2 "empty.yaml:1:1: error: the file is empty" check ${tmp}/empty.yaml)

# ---- invalid UTF-8 and huge names, in every kit's design file -------------------------------
string(ASCII 255 ff)
string(ASCII 254 fe)
file(WRITE ${tmp}/hacks_utf8.yaml "fabkit: hacks/1\nenvironment:\n  - {name: r${ff}${fe}, part: LongTensionRod}\n")
expect_run(2 "is not valid UTF-8" check ${tmp}/hacks_utf8.yaml)
expect_run(2 "is not valid UTF-8" solve ${tmp}/hacks_utf8.yaml -o ${tmp}/hacks_utf8_out)
if(EXISTS ${tmp}/hacks_utf8_out/result.json)
  message(FATAL_ERROR "a design with invalid UTF-8 left a result.json")
endif()
file(WRITE ${tmp}/rods_utf8.yaml "fabkit: rods/1\nname: x${ff}\nnodes: [[0, 0, 0], [100, 0, 0], [0, 100, 0]]\nedges: [[0, 1], [1, 2], [2, 0]]\n")
expect_run(2 "UTF-8" check ${tmp}/rods_utf8.yaml)
file(WRITE ${tmp}/flatpack_utf8.yaml "fabkit: flatpack/1\nname: box\ncomponents:\n  - {name: s${ff}, type: Rectangle, width: 100, height: 50}\n")
expect_run(2 "UTF-8" check ${tmp}/flatpack_utf8.yaml)
file(WRITE ${tmp}/templates_utf8.yaml "fabkit: templates/1\nmodel:\n  - {use: bookshelf, as: b${ff}}\n")
expect_run(2 "UTF-8" check ${tmp}/templates_utf8.yaml)
string(REPEAT "n" 1000000 long_name)
file(WRITE ${tmp}/long_name.yaml "fabkit: hacks/1\nenvironment:\n  - {name: r, part: ${long_name}}\n")
expect_run(2 "more bytes" check ${tmp}/long_name.yaml)  # echoed cut short, not 1 MB

# ---- outputs: never through a FIFO, a device or a link out of the directory -----------------
# One kit each way; every kit writes through the same atomic writer (core/file_io.h).
file(MAKE_DIRECTORY ${tmp}/hacks_out ${tmp}/rods_out ${tmp}/flatpack_out ${tmp}/templates_out ${tmp}/elsewhere)
execute_process(COMMAND mkfifo ${tmp}/hacks_out/result.json ${tmp}/rods_out/report.json
                               ${tmp}/flatpack_out/report.json ${tmp}/templates_out/bom.csv)
expect_run(5 "not a regular file" build ${ex}/hacks/bird_feeder.yaml -o ${tmp}/hacks_out -q)
expect_run(5 "not a regular file" build ${ex}/rods/twisted_prism.yaml -o ${tmp}/rods_out -q)
expect_run(5 "not a regular file" build ${ex}/flatpack/stool.yaml -o ${tmp}/flatpack_out -q)
expect_run(5 "not a regular file" build ${ex}/templates/table_with_shelf.yaml -o ${tmp}/templates_out -q)
foreach(f hacks_out/result.json rods_out/report.json flatpack_out/report.json templates_out/bom.csv)
  execute_process(COMMAND test -p ${tmp}/${f} RESULT_VARIABLE still_fifo)
  if(NOT still_fifo EQUAL 0)
    message(FATAL_ERROR "${f}: the FIFO was replaced")
  endif()
  # Every destination is checked before any is written: no half-written set beside the FIFO.
  get_filename_component(out_dir ${tmp}/${f} DIRECTORY)
  file(GLOB written ${out_dir}/*)
  list(LENGTH written count)
  if(NOT count EQUAL 1)
    message(FATAL_ERROR "${f}: a refused build still wrote ${written}")
  endif()
endforeach()
file(WRITE ${tmp}/elsewhere/victim "keep me")
file(MAKE_DIRECTORY ${tmp}/link_out)
file(CREATE_LINK ${tmp}/elsewhere/victim ${tmp}/link_out/scene.glb SYMBOLIC)
expect_run(5 "points out of its directory" build ${ex}/hacks/bird_feeder.yaml -o ${tmp}/link_out -q)
file(READ ${tmp}/elsewhere/victim victim)
if(NOT victim STREQUAL "keep me")
  message(FATAL_ERROR "a build wrote through a link out of its directory")
endif()
file(GLOB written ${tmp}/link_out/*)
if(NOT written STREQUAL "${tmp}/link_out/scene.glb")
  message(FATAL_ERROR "a refused build still wrote ${written}")
endif()
if(EXISTS /dev/null)
  file(MAKE_DIRECTORY ${tmp}/device_out)
  file(CREATE_LINK /dev/null ${tmp}/device_out/model.stl SYMBOLIC)
  expect_run(5 "model.stl" build ${ex}/flatpack/stool.yaml -o ${tmp}/device_out -q)
endif()

# ---- time limits: check, solve and build of every kit ---------------------------------------
expect_run(6 "stopped at the deadline after" check ${ex}/hacks/reading_nook.yaml --time-limit 0.001 -q)
expect_run(6 "stopped at the deadline after" solve ${ex}/hacks/reading_nook.yaml --time-limit 0.05 -q)
expect_run(6 "stopped at the deadline" build ${ex}/hacks/reading_nook.yaml -o ${tmp}/nook --time-limit 0.001 -q)
expect_run(6 "stopped at the deadline after" build ${ex}/rods/geodesic_dome.yaml -o ${tmp}/dome --time-limit 0.001 -q)
expect_run(6 "stopped at the deadline after" check ${ex}/rods/geodesic_dome.yaml --time-limit 0.001 -q)
expect_run(6 "stopped at the deadline after" check ${ex}/flatpack/bunk_bed.yaml --time-limit 0.001 -q)
expect_run(6 "nothing written" build ${ex}/flatpack/bunk_bed.yaml -o ${tmp}/bunk --time-limit 0.001 -q)
expect_run(6 "stopped at the deadline after" check ${ex}/templates/bench_with_backrest.yaml --time-limit 0.001 -q)
# A model with loads, cut before its parts are made: a time-out, not an unknown part (exit 2).
expect_run(6 "stopped at the deadline after" check ${ex}/templates/table_with_shelf.yaml --time-limit 0.001 -q)
expect_run(6 "nothing written" build ${ex}/templates/bench_with_backrest.yaml -o ${tmp}/bench --time-limit 0.001 -q)
foreach(d nook dome bunk bench)
  file(GLOB written ${tmp}/${d}/*)
  if(written)
    message(FATAL_ERROR "a build stopped at its deadline wrote ${written}")
  endif()
endforeach()
# Generous limits change nothing.
expect_run(0 "stable" solve ${ex}/hacks/bird_feeder.yaml --time-limit 600 -q)
expect_run(0 "valid" check ${ex}/flatpack/stool.yaml --time-limit 600 -q)
