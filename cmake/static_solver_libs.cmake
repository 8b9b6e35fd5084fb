# Ceres, as Debian ships it, is a static archive whose objects reach into SuiteSparse, LAPACK,
# BLAS, glog and gflags; a program linking it loads some twenty shared libraries more, and
# loading them is about a millisecond of every `fabkit solve` (docs/benchmarks.md, the whole
# process). A program that sets the target property FABKIT_STATIC_SOLVER links the static
# archives of those libraries instead, where every one of them is installed; libmetis (no
# static archive in Debian) and libunwind (its archive is not position-independent) stay shared.
#
# fabkit_solver_link: the link items, for target_link_libraries: Ceres::ceres, or the static set
# for a program with FABKIT_STATIC_SOLVER on (decided per program at generation time).

set(_fabkit_static_solver_archives
  libglog.a libgflags.a libspqr.a libcholmod.a libamd.a libcamd.a libccolamd.a libcolamd.a
  libsuitesparseconfig.a libcxsparse.a lapack/liblapack.a blas/libblas.a)
set(_fabkit_static_solver_items)
set(_fabkit_static_solver_ok TRUE)
get_target_property(_fabkit_ceres_archive Ceres::ceres IMPORTED_LOCATION_RELEASE)
if(NOT _fabkit_ceres_archive)
  get_target_property(_fabkit_ceres_archive Ceres::ceres IMPORTED_LOCATION_NONE)
endif()
if(NOT _fabkit_ceres_archive OR NOT _fabkit_ceres_archive MATCHES "\\.a$")
  set(_fabkit_static_solver_ok FALSE)
endif()
list(APPEND _fabkit_static_solver_items ${_fabkit_ceres_archive})
foreach(_archive IN LISTS _fabkit_static_solver_archives)
  # The reference LAPACK and BLAS by their own paths: liblapack.a is an alternative that may
  # name ATLAS's, which needs more archives.
  set(_path /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/${_archive})
  if(NOT EXISTS ${_path})
    set(_fabkit_static_solver_ok FALSE)
  endif()
  list(APPEND _fabkit_static_solver_items ${_path})
endforeach()
find_library(_fabkit_metis_shared NAMES metis libmetis.so.5)
find_library(_fabkit_unwind_shared NAMES unwind)
# The Fortran runtime LAPACK needs, and the OpenMP runtime SuiteSparse needs: the compiler's.
foreach(_runtime libgfortran.a libquadmath.a libgomp.a)
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=${_runtime}
                  OUTPUT_VARIABLE _fabkit_runtime_path OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT IS_ABSOLUTE "${_fabkit_runtime_path}" OR NOT EXISTS "${_fabkit_runtime_path}")
    set(_fabkit_static_solver_ok FALSE)
  endif()
  list(APPEND _fabkit_runtime_items ${_fabkit_runtime_path})
endforeach()
if(NOT _fabkit_metis_shared OR NOT _fabkit_unwind_shared)
  set(_fabkit_static_solver_ok FALSE)
endif()

if(_fabkit_static_solver_ok AND NOT FABKIT_FUZZ)
  add_library(fabkit_static_solver INTERFACE)
  target_link_libraries(fabkit_static_solver INTERFACE
    ${_fabkit_static_solver_items} ${_fabkit_metis_shared} ${_fabkit_unwind_shared}
    ${_fabkit_runtime_items} Threads::Threads rt m)
  set(fabkit_solver_link
      "$<IF:$<BOOL:$<TARGET_PROPERTY:FABKIT_STATIC_SOLVER>>,fabkit_static_solver,Ceres::ceres>")
  message(STATUS "fabkit: programs with FABKIT_STATIC_SOLVER link Ceres' libraries statically")
else()
  set(fabkit_solver_link Ceres::ceres)
  message(STATUS "fabkit: Ceres' libraries are linked shared everywhere (no static archives)")
endif()

# fabkit_lapack_link: LAPACK for fabkit::core's manifold solver (its large eigenbases). Static,
# with the Fortran runtime, in programs with FABKIT_STATIC_SOLVER; elsewhere the shared
# libraries, linked as needed so that the programs of kits that never use the solver do not
# load them (0.7 ms of every process start, measured).
find_package(LAPACK REQUIRED)
add_library(fabkit_shared_lapack INTERFACE)
target_link_libraries(fabkit_shared_lapack INTERFACE
  "-Wl,--push-state,--as-needed" ${LAPACK_LIBRARIES} "-Wl,--pop-state")
if(_fabkit_static_solver_ok AND NOT FABKIT_FUZZ)
  add_library(fabkit_static_lapack INTERFACE)
  target_link_libraries(fabkit_static_lapack INTERFACE
    /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/lapack/liblapack.a
    /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/blas/libblas.a ${_fabkit_runtime_items} m)
  set(fabkit_lapack_link
      "$<IF:$<BOOL:$<TARGET_PROPERTY:FABKIT_STATIC_SOLVER>>,fabkit_static_lapack,fabkit_shared_lapack>")
else()
  set(fabkit_lapack_link fabkit_shared_lapack)
endif()
