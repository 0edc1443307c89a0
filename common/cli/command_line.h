#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "common/base/result.h"

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

struct Endpoint {
    std::string host;
    uint16_t port = 0;
};

// "HOST:PORT" (the last colon splits, so "[::1]:9000" keeps its brackets for the resolver).
// Fails with "<option> <text>: expected HOST:PORT ..." for a missing host, a port that is not
// a number in [1, 65535], or trailing characters.
Result<Endpoint> parse_endpoint(std::string_view option, const std::string& text);

}  // namespace pathfarm
