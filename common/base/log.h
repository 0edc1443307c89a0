// Process-wide logging setup: one spdlog logger per process (STYLE.md §5.6).
#pragma once

#include <string_view>

namespace pathfarm {

// Installs the default logger named after the process, writing to stderr.
// level: trace, debug, info, warn, error, critical or off; unknown names fall back to info.
void init_logging(std::string_view process_name, std::string_view level = "info");

}  // namespace pathfarm
