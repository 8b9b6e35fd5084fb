# Warnings live on an INTERFACE target so that no global flags leak into dependencies.
add_library(fabkit_warnings INTERFACE)
add_library(fabkit::warnings ALIAS fabkit_warnings)
target_compile_options(fabkit_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow=local -Wno-unused-parameter>)
