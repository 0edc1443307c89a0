// GameWindow in a build without SDL2 (PATHFARM_WITH_SDL=OFF): opening it fails clearly.
#include "client/game_window.h"

namespace pathfarm::client {

struct GameWindow::Impl {};

GameWindow::GameWindow(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GameWindow::~GameWindow() = default;

Result<std::unique_ptr<GameWindow>> GameWindow::open(const std::string&) {
    return make_error(ErrorCode::unsupported,
                      "this build has no window (built without SDL2): run with --headless");
}
WindowInput GameWindow::poll(double) { return {}; }
Status GameWindow::show(int, int, const std::vector<uint8_t>&) { return {}; }
Status GameWindow::screenshot(const std::string&) { return {}; }

}  // namespace pathfarm::client
