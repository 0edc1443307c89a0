// Bounds on what a client's input may do to the game.
#include <algorithm>
#include <cmath>

#include "coordinator/game/game.h"

namespace pathfarm::coord {

PlayerInput bounded_input(PlayerInput raw) {
    for (std::size_t k = 0; k < raw.move.size(); ++k) {
        const float limit = k < 3 ? 10.0f : 3.14159265f;
        raw.move[k] = std::isfinite(raw.move[k]) ? std::clamp(raw.move[k], -limit, limit) : 0.0f;
    }
    return raw;
}

}  // namespace pathfarm::coord
