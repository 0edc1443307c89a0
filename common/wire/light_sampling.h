// How the coordinator asks tracers to choose emitters for next-event estimation
// (FrameAssignment.light_sampling; LightSelection on the tracer). Its own header so that the
// coordinator's option structs need not include the whole message set.
#pragma once

#include <cstdint>

namespace pathfarm::wire {

enum class LightSampling : uint8_t { power, tree, automatic };

}  // namespace pathfarm::wire
