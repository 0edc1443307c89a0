// What --light-sampler auto chose, in a backend's log: at info when the choice is new or has
// changed (an operator sees which sampler a scene renders with), else at debug.
#pragma once

#include <cstddef>
#include <optional>

#include <spdlog/spdlog.h>

#include "common/render/light_sampler.h"

namespace pathfarm::tracer {

inline void log_light_choice(const char* backend, LightSelection requested, LightSelection used,
                             const LightChoice& c, std::size_t emitters,
                             std::optional<LightSelection> before) {
    if (requested != LightSelection::automatic) return;
    const auto level = before == used ? spdlog::level::debug : spdlog::level::info;
    spdlog::log(level,
                "{}: light sampler auto chose {} for {} emitter(s) (the tree's variance {:.2f}x "
                "power's, median of {} receivers; the tree below {}x)",
                backend, light_selection_name(used), emitters, c.variance_ratio, c.receivers,
                LightChoice::kTreeBelow);
}

inline void log_light_choice(const char* backend, const LightSampler& lights,
                             std::optional<LightSelection> before) {
    log_light_choice(backend, lights.requested(), lights.selection(), lights.choice(),
                     lights.triangle_count(), before);
}

}  // namespace pathfarm::tracer
