# ctest "format": clang-format --dry-run --Werror over every C++ source of the repository.
file(GLOB_RECURSE sources
  ${SOURCE_DIR}/common/*.h ${SOURCE_DIR}/common/*.cpp
  ${SOURCE_DIR}/coordinator/*.h ${SOURCE_DIR}/coordinator/*.cpp
  ${SOURCE_DIR}/tracer-node/*.h ${SOURCE_DIR}/tracer-node/*.cpp
  ${SOURCE_DIR}/client/*.h ${SOURCE_DIR}/client/*.cpp
  ${SOURCE_DIR}/tools/*.h ${SOURCE_DIR}/tools/*.cpp
  ${SOURCE_DIR}/tests/*.h ${SOURCE_DIR}/tests/*.cpp
  ${SOURCE_DIR}/bench/*.h ${SOURCE_DIR}/bench/*.cpp)
execute_process(COMMAND ${CLANG_FORMAT} --dry-run --Werror --style=file ${sources}
                RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT result EQUAL 0)
  string(SUBSTRING "${err}" 0 4000 shown)
  message(FATAL_ERROR "clang-format: files need formatting (run scripts/format.sh):\n${shown}")
endif()
list(LENGTH sources count)
message(STATUS "format: ${count} files clean")
