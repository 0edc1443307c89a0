// make_game: the game for a scene.
#include "coordinator/game/default_scene_game.h"
#include "coordinator/game/free_camera.h"

namespace pathfarm::coord {

Result<std::unique_ptr<Game>> make_game(const std::string& kind, const std::string& scene_name,
                                        const SceneGraph& graph) {
    const bool is_default = scene_name == "builtin:default";
    if (kind == "free-camera" || (kind == "auto" && !is_default))
        return std::unique_ptr<Game>(std::make_unique<FreeCameraGame>(graph));
    if (kind == "default" || kind == "auto") {
        auto g = DefaultSceneGame::create(graph);
        if (!g) return g.error();
        return std::unique_ptr<Game>(std::move(*g));
    }
    return make_error(ErrorCode::invalid_argument,
                      "--game {}: unknown (known: auto, free-camera, default)", kind);
}

}  // namespace pathfarm::coord
