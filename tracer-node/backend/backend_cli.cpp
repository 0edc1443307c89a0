// Backend options for CLI11 command lines.
#include "tracer-node/backend/backend_cli.h"

#include <CLI/CLI.hpp>

namespace pathfarm::tracer {

void add_backend_options(CLI::App& app, std::string& backend, int& threads, int& cl_platform,
                         int& cl_device) {
    app.add_option("--backend", backend, "Render backend: embree or opencl")->capture_default_str();
    app.add_option("--threads", threads,
                   "Render threads (0: all; OpenCL: compute units of the device)")
        ->capture_default_str();
    app.add_option("--cl-platform", cl_platform, "OpenCL platform index (see clinfo -l)")
        ->capture_default_str();
    app.add_option("--cl-device", cl_device, "OpenCL device index within the platform")
        ->capture_default_str();
}

}  // namespace pathfarm::tracer
