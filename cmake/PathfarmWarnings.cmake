# Policy targets every pathfarm target links: warnings (and -Werror in CI), code generation,
# sanitizers.
add_library(pathfarm_warnings INTERFACE)
target_compile_options(pathfarm_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Wunused
  -Woverloaded-virtual -Wimplicit-fallthrough
  # GCC 12 reports false positives inside libstdc++'s std::string at -O3 (GCC bug 105651).
  $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>
  # In a unity build a source's own classes are no longer in the main file, so GCC takes a
  # member of a type in its anonymous namespace for a header's type that breaks the ODR.
  $<$<AND:$<CXX_COMPILER_ID:GNU>,$<BOOL:$<TARGET_PROPERTY:UNITY_BUILD>>>:-Wno-subobject-linkage>)
if(PATHFARM_WERROR)
  target_compile_options(pathfarm_warnings INTERFACE -Werror)
endif()

# Code generation, through the warnings target so that every target has it. No errno from the
# math functions (nothing here reads it): sqrt becomes the one instruction without a branch to
# the library for negative arguments, and calls the compiler can inline stay inline. The
# results are the same bits (IEEE square roots are exact either way): 2-3 % fewer
# instructions per sample, images identical (docs/performance.md).
add_library(pathfarm_codegen INTERFACE)
target_compile_options(pathfarm_codegen INTERFACE -fno-math-errno)
target_link_libraries(pathfarm_warnings INTERFACE pathfarm_codegen)

add_library(pathfarm_sanitize INTERFACE)
if(PATHFARM_SANITIZE)
  target_compile_options(pathfarm_sanitize INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(pathfarm_sanitize INTERFACE -fsanitize=address,undefined)
endif()
# Fuzz builds: coverage instrumentation everywhere; the fuzz targets link libFuzzer's main.
if(PATHFARM_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "PATHFARM_FUZZ needs clang (libFuzzer): CXX=clang++")
  endif()
  target_compile_options(pathfarm_sanitize INTERFACE -fsanitize=fuzzer-no-link)
endif()
