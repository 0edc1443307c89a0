// Game logic on the coordinator (DESIGN.md, "The frame" step 1): the player's input and the
// game's own clock edit the scene graph before each frame's commit is built. Runs on the frame
// loop's thread; ray queries see the last published acceleration structure.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "common/base/result.h"
#include "common/math/types.h"

namespace pathfarm::coord {

class SceneGraph;
class RayQueryService;

// One InputEvent from the client, as the game sees it.
struct PlayerInput {
    uint64_t sequence = 0;
    std::optional<Mat4> camera_to_world;  // an absolute pose (scripted clients)
    // Relative move: right, up, forward (metres, in the camera's horizontal frame), then yaw
    // and pitch (radians, positive turns left and looks up).
    std::array<float, 5> move{};
    bool action = false;
};

// An input as the game may take it from the network: at most 10 m and half a turn per input,
// non-finite values none (a hostile or broken client cannot teleport the camera or turn it
// into NaN). Poses are the decoder's to check (only finite ones are decoded).
PlayerInput bounded_input(PlayerInput raw);

class Game {
public:
    virtual ~Game() = default;
    // Applies one input at game time `clock_seconds`.
    virtual void on_input(const PlayerInput& input, double clock_seconds, SceneGraph& graph,
                          const RayQueryService& queries) = 0;
    // Time-driven logic for the frame at `clock_seconds`, before the scene graph advances.
    virtual void update(double clock_seconds, SceneGraph& graph) = 0;
    virtual std::string name() const = 0;
};

// "free-camera": walk and look with collisions, any scene. "default": builtin:default's game
// (moving ball, switching light, a door and a lamp the action key toggles). "auto": "default"
// for builtin:default, else "free-camera".
Result<std::unique_ptr<Game>> make_game(const std::string& kind, const std::string& scene_name,
                                        const SceneGraph& graph);

}  // namespace pathfarm::coord
