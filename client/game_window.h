// The interactive client's window (SDL2): shows frames, turns keyboard and mouse into the
// player's input. WASD walks, Space/Ctrl rise and sink, the mouse (or the arrow keys) looks
// around, E is the action key, Esc or closing the window quits. SDL stays behind this header.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/base/result.h"

namespace pathfarm::client {

struct WindowInput {
    std::array<float, 5> move{};  // right, up, forward (m), yaw, pitch (rad): the InputEvent's
    bool action = false;
    bool quit = false;
    bool any() const {
        return action || move[0] != 0.0f || move[1] != 0.0f || move[2] != 0.0f || move[3] != 0.0f ||
               move[4] != 0.0f;
    }
};

class GameWindow {
public:
    static constexpr float kWalkSpeed = 2.0f;        // m/s
    static constexpr float kTurnSpeed = 1.5f;        // rad/s with the arrow keys
    static constexpr float kMouseRadians = 0.0025f;  // per pixel of mouse motion

    static Result<std::unique_ptr<GameWindow>> open(const std::string& title);
    ~GameWindow();
    GameWindow(const GameWindow&) = delete;
    GameWindow& operator=(const GameWindow&) = delete;

    // Events since the last call, and the keys held for dt_seconds.
    WindowInput poll(double dt_seconds);
    // Shows a frame (sRGB RGB bytes, row 0 at the top); the window takes the first frame's size.
    Status show(int width, int height, const std::vector<uint8_t>& srgb8);
    // What the window shows now, as a PNG file.
    Status screenshot(const std::string& path);

private:
    struct Impl;
    explicit GameWindow(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace pathfarm::client
