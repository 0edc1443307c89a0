# Helpers that give every module the same shape: a static library plus thin executables.

# pathfarm_add_library(NAME SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
function(pathfarm_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS}
                        pathfarm_warnings pathfarm_sanitize)
endfunction()

# pathfarm_add_executable(NAME SOURCES ... DEPS ...)
function(pathfarm_add_executable name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} pathfarm_warnings pathfarm_sanitize)
endfunction()

# pathfarm_optional(FEATURE_VAR REASON): switch an optional part off with a status line,
# or fail when PATHFARM_STRICT_OPTIONS asks every requirement to be present.
function(pathfarm_optional feature_var reason)
  if(PATHFARM_STRICT_OPTIONS)
    message(FATAL_ERROR "${feature_var} requested but unavailable: ${reason}")
  endif()
  message(STATUS "${feature_var} disabled: ${reason}")
  set(${feature_var} OFF PARENT_SCOPE)
endfunction()
