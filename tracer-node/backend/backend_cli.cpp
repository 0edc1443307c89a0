// Backend options for CLI11 command lines.
#include "tracer-node/backend/backend_cli.h"

#include <map>

#include <CLI/CLI.hpp>

namespace pathfarm::tracer {

void add_backend_options(CLI::App& app, std::string& backend, int& threads, int& cl_platform,
                         int& cl_device, bool& texture_lod) {
    app.add_option("--backend", backend, "Render backend: embree or opencl")->capture_default_str();
    app.add_option("--threads", threads,
                   "Render threads (0: all; OpenCL: compute units of the device)")
        ->capture_default_str();
    app.add_option("--cl-platform", cl_platform, "OpenCL platform index (see clinfo -l)")
        ->capture_default_str();
    app.add_option("--cl-device", cl_device, "OpenCL device index within the platform")
        ->capture_default_str();
    app.add_option("--texture-lod", texture_lod,
                   "Texture level of detail: on reads coarser mip levels where a path's ray cone "
                   "is wide (past its first hit); off reads full resolution everywhere")
        ->transform(
            CLI::CheckedTransformer(std::map<std::string, bool>{{"on", true}, {"off", false}}))
        ->default_str(texture_lod ? "on" : "off");
}

}  // namespace pathfarm::tracer
