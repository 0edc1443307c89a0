// The farm's clients (DESIGN.md: input up, encoded frames down): native sessions and the HTTP
// port's browsers, the inputs they sent (applied at the next frame boundary), and the fan-out
// of every finished frame, encoded once per codec that some client asked for. Each client's
// frames echo the newest of *its own* inputs the frame shows, so that every client measures
// input-to-frame latency against its own sequence numbers. Thread-safe: the network and HTTP
// threads add clients and deliver inputs; the frame loop takes inputs; the display sends.
#pragma once

#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "common/film/film.h"
#include "common/film/h264_codec.h"
#include "common/net/session.h"
#include "coordinator/frame/farm_metrics.h"
#include "coordinator/frame/frame_encoder.h"
#include "coordinator/game/game.h"

namespace pathfarm::coord {

class WebPort;

// What a frame shows, beyond its picture (the browser's overlay prints it).
struct ShownFrame {
    uint64_t frame = 0;
    int render_width = 0, render_height = 0, spp = 0;
    int width = 0, height = 0;  // the picture's (set by the hub)
};

class ClientHub {
public:
    using Clock = std::chrono::steady_clock;
    ClientHub(int jpeg_quality, FarmMetrics& metrics)
        : jpeg_quality_(jpeg_quality), metrics_(metrics) {}

    // --- network thread
    void add(std::shared_ptr<net::Session> session);  // installs its handlers
    // --- HTTP thread: the browsers of `port` (set before any joins; it outlives the hub's use)
    void attach(WebPort* port) { web_ = port; }
    void browser_joined(uint64_t id, bool h264);
    void browser_needs_key(uint64_t id);  // its stream lost a picture
    void browser_input(uint64_t id, const PlayerInput& input);
    void browser_left(uint64_t id);

    // --- frame loop
    // Inputs received since the last call, in arrival order; they take effect in `frame`.
    std::vector<PlayerInput> take_inputs(uint64_t frame);
    // --- display thread
    // Encodes `image` once per codec in use and sends it to every client with the newest of
    // that client's inputs applied up to the frame.
    void send(const FloatImage& image, const ShownFrame& shown);
    std::size_t size() const;  // native clients and browsers
    // No client is accepted from now on; returns the sessions for the caller to close.
    std::vector<std::shared_ptr<net::Session>> stop_accepting();

private:
    // Browsers and native sessions in one map: a browser's key has the top bit set.
    static constexpr uint64_t kBrowserBit = uint64_t(1) << 63;
    // A native client with more than max(this, two of this frame's messages) unsent skips the
    // frame; one that skips frames for kBackedUpLimit is disconnected.
    static constexpr std::size_t kMinUnsentLimit = std::size_t(1) << 20;
    static constexpr std::chrono::seconds kBackedUpLimit{5};
    struct Client {
        std::shared_ptr<net::Session> session;  // none: a browser
        FrameCodec codec = FrameCodec::jpeg;
        bool h264 = false;      // a browser that decodes H.264
        bool needs_key = true;  // H.264: the next picture it gets must be an IDR frame
        // Native: since when it has had too much unsent to be sent another frame.
        std::optional<Clock::time_point> backed_up_since;
    };
    struct Pending {
        uint64_t client;
        PlayerInput input;
        Clock::time_point received;
    };
    struct FrameInputs {  // what a frame applied, for its echoes and latencies
        uint64_t frame;
        std::map<uint64_t, uint64_t> newest;  // per client, the newest input applied by then
        std::vector<Clock::time_point> received;
    };
    void on_input(uint64_t id, const std::string& bytes);
    void queue_input(uint64_t key, const PlayerInput& input);
    FrameInputs inputs_of(uint64_t frame);
    void count_clients_locked();
    // The browsers' H.264 stream (one encoder, every H.264 browser sees the same pictures);
    // none when it cannot be encoded (those browsers get JPEG).
    std::optional<H264Picture> encode_h264(const FloatImage& image, bool key);
    bool send_native(const Client& c, std::string message, std::size_t& bytes);
    void note_backlogs(const std::vector<uint64_t>& sent, const std::vector<uint64_t>& backed_up);
    void send_to_browser(uint64_t key, const Client& c, const std::string& jpeg,
                         const std::optional<H264Picture>& video, const ShownFrame& shown,
                         uint64_t echo, std::size_t& bytes);

    int jpeg_quality_;
    FarmMetrics& metrics_;
    WebPort* web_ = nullptr;
    std::unique_ptr<H264Encoder> h264_;  // display thread
    bool h264_failed_ = false;
    mutable std::mutex mutex_;
    std::map<uint64_t, Client> clients_;
    std::vector<Pending> pending_;
    std::map<uint64_t, uint64_t> applied_;  // per client, the newest input taken
    std::deque<FrameInputs> frames_;        // taken, not yet shown
    bool accepting_ = true;
};

}  // namespace pathfarm::coord
