// The farm's options, checked before anything starts.
#include "coordinator/session/farm_options_check.h"

#include <cmath>
#include <utility>

#include "common/wire/messages.h"

namespace pathfarm::coord {

Status check_farm_options(const FarmOptions& o) {
    // Each option named with its value. A frame larger than the wire carries was taken and
    // failed only when a tracer came: its assignments could not be decoded.
    for (const auto& [option, side] : {std::pair{"--width", o.width}, {"--height", o.height}})
        if (side <= 0 || uint32_t(side) > wire::kMaxImageSide)
            return make_error(ErrorCode::invalid_argument, "{} {}: must be 1..{}", option, side,
                              wire::kMaxImageSide);
    if (o.spp <= 0)
        return make_error(ErrorCode::invalid_argument, "--spp {}: must be positive", o.spp);
    if (o.deadline_ms <= 0)
        return make_error(ErrorCode::invalid_argument, "--deadline-ms {}: must be positive",
                          o.deadline_ms);
    if (o.min_tracers < 0)
        return make_error(ErrorCode::invalid_argument, "--min-tracers {}: must be >= 0",
                          o.min_tracers);
    if (!(o.fps > 0.0))
        return make_error(ErrorCode::invalid_argument, "--fps {}: must be positive", o.fps);
    if (!std::isfinite(o.fps))  // every frame at time 0: a game that never moves
        return make_error(ErrorCode::invalid_argument, "--fps {}: must be finite", o.fps);
    if (o.max_depth < 0 || o.max_depth > 1024)  // was sent to the tracers as it was
        return make_error(ErrorCode::invalid_argument, "--max-depth {}: must be 0..1024",
                          o.max_depth);
    if (o.jpeg_quality < 1 || o.jpeg_quality > 100)
        return make_error(ErrorCode::invalid_argument, "--jpeg-quality {}: must be in [1, 100]",
                          o.jpeg_quality);
    if (!(o.extra_samples >= 0.0 && o.extra_samples <= 1.0))
        return make_error(ErrorCode::invalid_argument, "--extra-samples {}: must be in [0, 1]",
                          o.extra_samples);
    if (!(o.render_budget >= 0.3 && o.render_budget <= 1.0))
        return make_error(ErrorCode::invalid_argument, "--render-budget {}: must be in [0.3, 1]",
                          o.render_budget);
    if (o.extra_samples > 0.0 && !o.fixed_spp)
        return make_error(ErrorCode::invalid_argument,
                          "--extra-samples needs --fixed-spp (workload scaling chooses its own)");
    for (const auto& [option, scale] :
         {std::pair{"--min-rr-scale", o.min_rr_scale}, {"--min-resolution", o.min_resolution}})
        if (!(scale > 0.0f && scale <= 1.0f))
            return make_error(ErrorCode::invalid_argument, "{} {}: must be in (0, 1]", option,
                              scale);
    if (!(o.target_fps >= 0.0) || !std::isfinite(o.target_fps))
        return make_error(ErrorCode::invalid_argument,
                          "--target-fps {}: must be >= 0 and finite (0: --fps)", o.target_fps);
    if (!(o.speed_smoothing > 0.0 && o.speed_smoothing <= 1.0))
        return make_error(ErrorCode::invalid_argument, "--speed-smoothing {}: must be in (0, 1]",
                          o.speed_smoothing);
    return {};
}

}  // namespace pathfarm::coord
