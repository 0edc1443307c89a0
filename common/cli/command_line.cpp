#include "common/cli/command_line.h"

#include <CLI/CLI.hpp>

#include "common/base/log.h"

namespace pathfarm {

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv,
                                      std::string_view program, const std::string& default_level) {
    std::string log_level = default_level;
    app.add_option("--log-level", log_level, "trace, debug, info, warn or error")
        ->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    init_logging(program, log_level);
    return std::nullopt;
}

}  // namespace pathfarm
