# Policy targets every pathfarm target links: warnings (and -Werror in CI), sanitizers.
add_library(pathfarm_warnings INTERFACE)
target_compile_options(pathfarm_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Wunused
  -Woverloaded-virtual -Wimplicit-fallthrough
  # GCC 12 reports false positives inside libstdc++'s std::string at -O3 (GCC bug 105651).
  $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)
if(PATHFARM_WERROR)
  target_compile_options(pathfarm_warnings INTERFACE -Werror)
endif()

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
