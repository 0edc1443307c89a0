// The farm's clients (DESIGN.md: input up, encoded frames down): their sessions, the inputs
// they sent (bounded and applied at the next frame boundary), and the fan-out of every finished
// frame, encoded once per codec that some client asked for. Thread-safe: the network thread
// adds sessions and delivers inputs; the frame loop takes inputs and sends frames.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "common/film/film.h"
#include "common/net/session.h"
#include "coordinator/frame/frame_encoder.h"
#include "coordinator/game/game.h"

namespace pathfarm::wire {
struct Input;
}

namespace pathfarm::coord {

class ClientHub {
public:
    explicit ClientHub(int jpeg_quality) : jpeg_quality_(jpeg_quality) {}

    // --- network thread
    void add(std::shared_ptr<net::Session> session);  // installs its handlers

    // --- frame loop
    // Inputs received since the last call, in arrival order.
    std::vector<PlayerInput> take_inputs();
    // Encodes `image` once per codec in use and sends it with the frame number and the newest
    // input it shows (for the client's latency measurement).
    void send(const FloatImage& image, uint64_t frame, uint64_t last_input_sequence);
    std::size_t size() const;
    // No client is accepted from now on; returns the sessions for the caller to close.
    std::vector<std::shared_ptr<net::Session>> stop_accepting();

private:
    struct Client {
        std::shared_ptr<net::Session> session;
        FrameCodec codec = FrameCodec::jpeg;
    };
    void on_input(uint64_t id, const std::string& bytes);

    int jpeg_quality_;
    mutable std::mutex mutex_;
    std::map<uint64_t, Client> clients_;
    std::vector<PlayerInput> pending_;
    bool accepting_ = true;
};

// A client's input as the game takes it: at most 10 m and half a turn per input, non-finite
// values none (a hostile or broken client cannot teleport the camera or turn it into NaN).
PlayerInput bounded_input(const wire::Input& in);

}  // namespace pathfarm::coord
