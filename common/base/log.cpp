// Default logger for a pathfarm process.
#include "common/base/log.h"

#include <memory>
#include <string>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace pathfarm {

void init_logging(std::string_view process_name, std::string_view level) {
    auto logger = spdlog::stderr_color_mt(std::string(process_name));
    logger->set_pattern("[%H:%M:%S.%e] [%n] [%^%l%$] %v");
    auto parsed = spdlog::level::from_str(std::string(level));
    if (parsed == spdlog::level::off && level != "off") parsed = spdlog::level::info;
    logger->set_level(parsed);
    spdlog::set_default_logger(std::move(logger));
}

}  // namespace pathfarm
