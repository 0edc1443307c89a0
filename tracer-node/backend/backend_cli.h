// The backend options pathfarm-render and pathfarm-tracer share on their command lines.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace pathfarm::tracer {

// Adds --backend, --threads, --cl-platform, --cl-device and --texture-lod (on|off).
void add_backend_options(CLI::App& app, std::string& backend, int& threads, int& cl_platform,
                         int& cl_device, bool& texture_lod);

}  // namespace pathfarm::tracer
