# Solves bundled examples and runs the Khronos glTF validator on each scene.glb.
set(out ${CMAKE_CURRENT_BINARY_DIR}/gltf_validator_out)
file(REMOVE_RECURSE ${out})
set(scenes)
foreach(example bird_feeder toothbrush_holder basket_between_rods reading_nook)
  execute_process(COMMAND ${FABKIT} solve ${SOURCE_DIR}/examples/hacks/${example}.yaml -q -o ${out}/${example}
                  RESULT_VARIABLE code OUTPUT_VARIABLE text ERROR_VARIABLE text)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "fabkit solve ${example}: exit ${code}\n${text}")
  endif()
  list(APPEND scenes ${out}/${example}/scene.glb)
endforeach()
# A design that falls apart highlights the slipping connection in its scene.
execute_process(COMMAND ${FABKIT} solve ${SOURCE_DIR}/examples/failing/hook_on_tilted_rod.yaml -q -o ${out}/slip
                RESULT_VARIABLE code OUTPUT_QUIET ERROR_QUIET)
list(APPEND scenes ${out}/slip/scene.glb)
# Flat-pack furniture: every piece of every bundled example (the locked picnic table is built
# too: its check fails, its scene is written).
foreach(example bookend reading_desk stool computer_desk simple_table picnic_table
                picnic_table_locked bookshelf bunk_bed tv_console box_with_lid)
  execute_process(COMMAND ${FABKIT} build ${SOURCE_DIR}/examples/flatpack/${example}.yaml -q -o ${out}/flatpack_${example}
                  RESULT_VARIABLE code OUTPUT_VARIABLE text ERROR_VARIABLE text)
  if(NOT EXISTS ${out}/flatpack_${example}/scene.glb)
    message(FATAL_ERROR "fabkit build ${example}: exit ${code}, no scene.glb\n${text}")
  endif()
  list(APPEND scenes ${out}/flatpack_${example}/scene.glb)
endforeach()
execute_process(COMMAND ${NODE} ${SOURCE_DIR}/tools/gltf-check/check-glb.mjs ${scenes}
                RESULT_VARIABLE code OUTPUT_VARIABLE text ERROR_VARIABLE text)
message("${text}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "the glTF validator rejected a scene")
endif()
