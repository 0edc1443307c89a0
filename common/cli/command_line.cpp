#include "common/cli/command_line.h"

#include <charconv>

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

Result<Endpoint> parse_endpoint(std::string_view option, const std::string& text) {
    const auto colon = text.rfind(':');
    unsigned port = 0;
    if (colon != std::string::npos && colon > 0) {
        const char* first = text.data() + colon + 1;
        const char* last = text.data() + text.size();
        const auto [end, ec] = std::from_chars(first, last, port);
        if (ec == std::errc() && end == last && first != last && port >= 1 && port <= 65535)
            return Endpoint{text.substr(0, colon), uint16_t(port)};
    }
    return make_error(ErrorCode::invalid_argument,
                      "{} {}: expected HOST:PORT with a port in [1, 65535]", option, text);
}

}  // namespace pathfarm
