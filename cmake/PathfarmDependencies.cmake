# Third-party packages (Debian 12). See ../shared/TOOLCHAIN.md for the pitfalls solved here.
find_package(Threads REQUIRED)
find_package(glm CONFIG REQUIRED)
find_package(spdlog CONFIG REQUIRED)
find_package(TBB CONFIG REQUIRED)
find_package(ZLIB REQUIRED)
find_package(TinyGLTF CONFIG REQUIRED)
find_package(tinyobjloader CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(zstd CONFIG REQUIRED)

# OpenImageIO's CMake config is broken on Debian 12 (TOOLCHAIN.md pitfall 1): use pkg-config.
find_package(PkgConfig REQUIRED)
pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET GLOBAL OpenImageIO>=2.4)
add_library(OpenImageIO::OpenImageIO ALIAS PkgConfig::OIIO)
pkg_check_modules(TURBOJPEG REQUIRED IMPORTED_TARGET GLOBAL libturbojpeg)
# libavcodec (with libx264) and libswscale: H.264 frames (common/film/h264_codec.cpp).
pkg_check_modules(LIBAV REQUIRED IMPORTED_TARGET GLOBAL libavcodec libavutil libswscale)

add_compile_definitions(GLM_ENABLE_EXPERIMENTAL)

if(PATHFARM_WITH_EMBREE)
  find_package(embree 3 CONFIG QUIET)
  if(NOT embree_FOUND)
    pathfarm_optional(PATHFARM_WITH_EMBREE "embree 3 not found (apt-get install libembree-dev)")
  endif()
endif()

if(PATHFARM_WITH_OPENCL)
  find_package(OpenCL QUIET)
  if(NOT OpenCL_FOUND OR NOT EXISTS "${OpenCL_INCLUDE_DIR}/CL/opencl.hpp")
    pathfarm_optional(PATHFARM_WITH_OPENCL
      "OpenCL not found (apt-get install ocl-icd-opencl-dev opencl-clhpp-headers pocl-opencl-icd)")
  endif()
endif()
