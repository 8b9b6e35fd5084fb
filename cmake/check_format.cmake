# Fails if any C++ source of the project differs from what clang-format makes of it. Every
# module is covered, including kits added later; build trees, node_modules and the web editor
# (TypeScript) are not C++.
file(GLOB_RECURSE sources ${SOURCE_DIR}/*.cpp ${SOURCE_DIR}/*.h ${SOURCE_DIR}/*.hpp)
list(FILTER sources EXCLUDE REGEX "^${SOURCE_DIR}/(build[^/]*|web|tools|\\.git)/")
list(FILTER sources EXCLUDE REGEX "/node_modules/")
execute_process(COMMAND ${CLANG_FORMAT} --dry-run --Werror ${sources}
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "clang-format would change these files (run clang-format -i):\n${err}")
endif()
