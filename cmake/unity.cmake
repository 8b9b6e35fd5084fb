# Batched ("unity") compilation: each library and test program of the kits compiles its
# sources in batches of eight, so that Eigen, fmt and the standard library are parsed once
# per batch instead of once per file; most of a clean build is that parsing (docs/benchmarks.md).
# Off for incremental work on one file: -DFABKIT_UNITY_BUILD=OFF.
# The front ends (server, CLI, Python) stay per file: each of their files uses one kit's
# namespace, and the kits' names (Design, BuildOptions, ...) would meet in a batch.
option(FABKIT_UNITY_BUILD "Compile each library's sources in batches (faster clean builds)" ON)

function(fabkit_batched)
  if(FABKIT_UNITY_BUILD)
    foreach(target IN LISTS ARGN)
      set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
    endforeach()
  endif()
endfunction()
