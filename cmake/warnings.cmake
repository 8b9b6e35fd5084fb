# Warnings live on an INTERFACE target so that no global flags leak into dependencies.
# (clang, used by the sanitizer build, has no -Wshadow=local.)
add_library(fabkit_warnings INTERFACE)
add_library(fabkit::warnings ALIAS fabkit_warnings)
target_compile_options(fabkit_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic>
  $<$<CXX_COMPILER_ID:GNU>:-Wshadow=local>
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wno-unused-parameter>)
