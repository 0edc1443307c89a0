// Failure path of PF_CHECK: log through the process logger, then abort.
#include "common/base/check.h"

#include <spdlog/spdlog.h>

namespace pathfarm::detail {

void check_failed(std::string_view file, int line, std::string_view what) {
    spdlog::critical("check failed at {}:{}: {}", file, line, what);
    spdlog::shutdown();
    std::abort();
}

}  // namespace pathfarm::detail
