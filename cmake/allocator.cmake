# The programs that solve link mimalloc (Debian's libmimalloc-dev) in place of glibc's malloc.
# A solve allocates and frees many small Eigen matrices on several threads at once; measured
# (docs/benchmarks.md, "The fourth stop of 2026-12-05"): the solve stage 2–10 % faster, whole
# `fabkit solve` processes within noise. Numbers do not move: only where memory comes from
# changes.
# Not under the sanitizers (they bring their own allocator) and not in the Python module (a
# library loaded into a running interpreter cannot take malloc over safely).
#
# fabkit_allocator: link it into a program (an empty interface target under the sanitizers).
add_library(fabkit_allocator INTERFACE)
if(NOT FABKIT_FUZZ)
  find_library(FABKIT_MIMALLOC_LIBRARY NAMES mimalloc REQUIRED)
  # Needed although nothing names it: its malloc and free replace libc's by being loaded first.
  target_link_libraries(fabkit_allocator INTERFACE
    "-Wl,--push-state,--no-as-needed" ${FABKIT_MIMALLOC_LIBRARY} "-Wl,--pop-state")
endif()
