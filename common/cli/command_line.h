#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace CLI {
class App;
}

namespace pathfarm {

// The ending every pathfarm process's command line shares: adds --log-level (default
// `default_level`), parses, and starts logging as `program`. Returns the exit code when the
// process must end now (0 after --help, 2 on a usage error, which CLI11 has printed), else
// nullopt.
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv,
                                      std::string_view program,
                                      const std::string& default_level = "info");

}  // namespace pathfarm
