// The farm's options, checked before anything starts: each error names the option and its value
// in one line (the process exits 2 with it).
#pragma once

#include "common/base/result.h"
#include "coordinator/session/farm_coordinator.h"

namespace pathfarm::coord {

Status check_farm_options(const FarmOptions& options);

}  // namespace pathfarm::coord
