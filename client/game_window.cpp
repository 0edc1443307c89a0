// SDL2 window, renderer and a streaming RGB24 texture.
#include "client/game_window.h"

#include <SDL.h>

#include "common/film/image_io.h"

namespace pathfarm::client {

struct GameWindow::Impl {
    SDL_Window* window = nullptr;
    SDL_Renderer* renderer = nullptr;
    SDL_Texture* texture = nullptr;
    int width = 0, height = 0;  // of the texture (the frames)
    bool relative_mouse = false;
    std::string title;

    ~Impl() {
        if (texture) SDL_DestroyTexture(texture);
        if (renderer) SDL_DestroyRenderer(renderer);
        if (window) SDL_DestroyWindow(window);
        SDL_QuitSubSystem(SDL_INIT_VIDEO);
    }
};

GameWindow::GameWindow(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GameWindow::~GameWindow() = default;

Result<std::unique_ptr<GameWindow>> GameWindow::open(const std::string& title) {
    if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0)
        return make_error(ErrorCode::unsupported,
                          "no window: {} (set DISPLAY, or run with --headless)", SDL_GetError());
    auto impl = std::make_unique<Impl>();
    const std::string driver = SDL_GetCurrentVideoDriver() ? SDL_GetCurrentVideoDriver() : "";
    if (driver == "dummy" || driver == "offscreen" || driver.empty())
        return make_error(ErrorCode::unsupported,
                          "no window: no display (SDL video driver \"{}\"); set DISPLAY, or run "
                          "with --headless",
                          driver);
    impl->title = title;
    // Created now so that a missing display fails before connecting; sized by the first frame.
    impl->window = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                    640, 360, SDL_WINDOW_SHOWN);
    if (!impl->window)
        return make_error(ErrorCode::unsupported, "no window: {} (run with --headless)",
                          SDL_GetError());
    impl->renderer = SDL_CreateRenderer(impl->window, -1, 0);
    if (!impl->renderer) return make_error(ErrorCode::io_error, "renderer: {}", SDL_GetError());
    impl->relative_mouse = SDL_SetRelativeMouseMode(SDL_TRUE) == 0;
    return std::unique_ptr<GameWindow>(new GameWindow(std::move(impl)));
}

Status GameWindow::show(int width, int height, const std::vector<uint8_t>& srgb8) {
    Impl& s = *impl_;
    if (!s.texture) {  // the first frame: small frames get a window twice their size
        const int scale = width < 640 ? 2 : 1;
        SDL_SetWindowSize(s.window, width * scale, height * scale);
    }
    if (!s.texture || s.width != width || s.height != height) {
        if (s.texture) SDL_DestroyTexture(s.texture);
        s.texture = SDL_CreateTexture(s.renderer, SDL_PIXELFORMAT_RGB24,
                                      SDL_TEXTUREACCESS_STREAMING, width, height);
        if (!s.texture) return make_error(ErrorCode::io_error, "texture: {}", SDL_GetError());
        s.width = width;
        s.height = height;
    }
    if (SDL_UpdateTexture(s.texture, nullptr, srgb8.data(), width * 3) != 0 ||
        SDL_RenderClear(s.renderer) != 0 ||
        SDL_RenderCopy(s.renderer, s.texture, nullptr, nullptr) != 0)
        return make_error(ErrorCode::io_error, "drawing the frame: {}", SDL_GetError());
    SDL_RenderPresent(s.renderer);
    return {};
}

WindowInput GameWindow::poll(double dt) {
    WindowInput in;
    SDL_Event e;
    while (SDL_PollEvent(&e)) {
        if (e.type == SDL_QUIT) in.quit = true;
        if (e.type == SDL_KEYDOWN && !e.key.repeat) {
            if (e.key.keysym.sym == SDLK_ESCAPE) in.quit = true;
            if (e.key.keysym.sym == SDLK_e) in.action = true;
        }
        // Without relative mouse mode (no pointer grab), look while the left button is held.
        if (e.type == SDL_MOUSEMOTION &&
            (impl_->relative_mouse || (e.motion.state & SDL_BUTTON_LMASK))) {
            in.move[3] -= float(e.motion.xrel) * kMouseRadians;
            in.move[4] -= float(e.motion.yrel) * kMouseRadians;
        }
    }
    const Uint8* keys = SDL_GetKeyboardState(nullptr);
    const float step = kWalkSpeed * float(dt), turn = kTurnSpeed * float(dt);
    in.move[0] += step * float(keys[SDL_SCANCODE_D] - keys[SDL_SCANCODE_A]);
    in.move[1] += step * float(keys[SDL_SCANCODE_SPACE] - keys[SDL_SCANCODE_LCTRL]);
    in.move[2] += step * float(keys[SDL_SCANCODE_W] - keys[SDL_SCANCODE_S]);
    in.move[3] += turn * float(keys[SDL_SCANCODE_LEFT] - keys[SDL_SCANCODE_RIGHT]);
    in.move[4] += turn * float(keys[SDL_SCANCODE_UP] - keys[SDL_SCANCODE_DOWN]);
    return in;
}

Status GameWindow::screenshot(const std::string& path) {
    Impl& s = *impl_;
    if (!s.renderer) return make_error(ErrorCode::invalid_argument, "{}: no frame shown yet", path);
    int w = 0, h = 0;
    if (SDL_GetRendererOutputSize(s.renderer, &w, &h) != 0)
        return make_error(ErrorCode::io_error, "screenshot: {}", SDL_GetError());
    std::vector<uint8_t> rgb(std::size_t(w) * h * 3);
    // Draw the shown frame again: after SDL_RenderPresent the back buffer is undefined.
    if (SDL_RenderClear(s.renderer) != 0 ||
        SDL_RenderCopy(s.renderer, s.texture, nullptr, nullptr) != 0 ||
        SDL_RenderReadPixels(s.renderer, nullptr, SDL_PIXELFORMAT_RGB24, rgb.data(), w * 3) != 0)
        return make_error(ErrorCode::io_error, "screenshot: {}", SDL_GetError());
    return write_rgb8(path, w, h, rgb);
}

}  // namespace pathfarm::client
