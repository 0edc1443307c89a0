// The client loop: frames arrive on the network thread; this thread decodes, shows or
// writes them, and gathers and sends input.
#include "client/client.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include <spdlog/spdlog.h>

#include "client/contact_sheet.h"
#include "client/frame_output.h"
#include "client/game_window.h"
#include "common/base/folder.h"
#include "common/base/timer.h"
#include "common/film/float_codec.h"
#include "common/film/h264_codec.h"
#include "common/film/image_io.h"
#include "common/film/jpeg_codec.h"
#include "common/film/tonemap.h"
#include "common/math/transform.h"
#include "common/net/session.h"
#include "common/wire/messages.h"

namespace pathfarm::client {
namespace {

class FrameQueue {
public:
    void push(std::string m) {
        std::lock_guard lock(mutex_);
        frames_.push_back(std::move(m));
        cv_.notify_one();
    }
    void close(std::string reason) {
        std::lock_guard lock(mutex_);
        closed_ = true;
        reason_ = std::move(reason);
        cv_.notify_one();
    }
    // The next message, or nothing after `wait` (or once closed and drained).
    std::optional<std::string> pop_for(std::chrono::milliseconds wait) {
        std::unique_lock lock(mutex_);
        cv_.wait_for(lock, wait, [&] { return !frames_.empty() || closed_; });
        if (frames_.empty()) return std::nullopt;
        std::string m = std::move(frames_.front());
        frames_.pop_front();
        return m;
    }
    bool drained() {
        std::lock_guard lock(mutex_);
        return closed_ && frames_.empty();
    }
    std::string reason() {
        std::lock_guard lock(mutex_);
        return reason_;
    }

private:
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<std::string> frames_;
    bool closed_ = false;
    std::string reason_;
};

class InputSender {
public:
    InputSender(std::shared_ptr<net::Session> session, LatencyStats& stats)
        : session_(std::move(session)), stats_(stats) {}
    // After a reconnection: later inputs go to the new session, their numbers go on.
    void attach(std::shared_ptr<net::Session> session) { session_ = std::move(session); }

    void send(const std::optional<Mat4>& pose, const std::array<float, 5>& move, bool action) {
        const auto now = LatencyStats::Clock::now();
        wire::Input in;
        in.sequence = ++sequence_;
        in.timestamp_us = uint64_t(
            std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count());
        in.camera_to_world = pose;
        if (move != std::array<float, 5>{}) in.move.assign(move.begin(), move.end());
        in.action = action;
        stats_.input_sent(sequence_, now);
        session_->send(wire::encode_input(in));
    }

private:
    std::shared_ptr<net::Session> session_;
    LatencyStats& stats_;
    uint64_t sequence_ = 0;
};

int codec_for(OutputFormat f) {
    switch (f) {
        case OutputFormat::exr:
            return int(wire::FrameCodec::float_zstd);
        case OutputFormat::png:
            return int(wire::FrameCodec::png);
        case OutputFormat::h264:
            return int(wire::FrameCodec::h264);
        case OutputFormat::jpeg:
            break;
    }
    return int(wire::FrameCodec::jpeg);
}

}  // namespace

Result<std::map<uint64_t, Mat4>> read_camera_script(const std::string& path) {
    std::ifstream in(path);
    if (!in) return make_error(ErrorCode::not_found, "--script {}: cannot read", path);
    std::map<uint64_t, Mat4> poses;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        line = line.substr(0, line.find('#'));
        std::istringstream ls(line);
        uint64_t frame;
        Vec3 eye, target;
        if (!(ls >> frame)) continue;  // blank or comment line
        if (!(ls >> eye.x >> eye.y >> eye.z >> target.x >> target.y >> target.z) || eye == target)
            return make_error(ErrorCode::parse_error,
                              "{}:{}: expected FRAME eye_x eye_y eye_z target_x target_y target_z",
                              path, n);
        poses[frame] = look_at_camera(eye, target, Vec3(0, 1, 0));
    }
    return poses;
}

// One run of the client: frames in (shown, written, counted), input out.
class ClientRun {
public:
    ClientRun(const ClientOptions& o, std::map<uint64_t, Mat4> script,
              std::shared_ptr<net::Session> session, LatencyStats& stats, GameWindow* window)
        : o_(o),
          script_(std::move(script)),
          stats_(stats),
          window_(window),
          input_(std::move(session), stats),
          sheet_(o.frames > 0 ? (o.frames + 15) / 16 : 1) {
        if (auto first = script_.find(0); first != script_.end())
            input_.send(first->second, {}, false);
    }

    // A new session after the old one was lost: inputs go there, and an H.264 stream starts
    // again at the IDR frame the coordinator makes for a joining client.
    void reconnected(std::shared_ptr<net::Session> session) {
        input_.attach(std::move(session));
        video_.reset();
    }

    // Shows one received frame; false when the client is done (its frame count reached, or
    // the window failed).
    Result<bool> on_frame(const std::string& bytes) {
        auto f = wire::decode_frame(bytes);
        if (!f) {  // a bad frame is skipped, the client goes on
            spdlog::error("{}", f.error().message);
            return true;
        }
        stats_.frame_arrived(f->frame, f->last_input_sequence, Clock::now());
        if (report_.frames == 0) timer_.reset();  // between frames, not connection time
        if (!video_) {
            auto opened = H264Decoder::open();
            if (!opened) return opened.error();
            video_ = std::move(*opened);
        }
        auto frame = decode_image(*f, *video_);
        if (!frame) {
            spdlog::error("{}", frame.error().message);
            return true;
        }
        if (Status s = write_frame(o_, *f, *frame); !s) spdlog::error("{}", s.error().message);
        if (window_) {
            if (Status s = window_->show(frame->width, frame->height, frame->srgb8); !s)
                return s.error();
            if (report_.frames + 1 == o_.screenshot_frame && !o_.screenshot.empty())
                if (Status s = window_->screenshot(o_.screenshot); !s) return s.error();
        }
        sheet_.add(uint64_t(report_.frames), frame->width, frame->height, frame->srgb8);
        ++report_.frames;
        if (auto next = script_.find(f->frame + 1); next != script_.end())
            input_.send(next->second, {}, false);
        return !(o_.frames > 0 && report_.frames >= o_.frames);
    }

    // Gathers input continuously (the window, or a scripted player that turns and acts once a
    // second) and sends it at most every 16 ms, and with every action. False: quit.
    bool poll() {
        const auto now = Clock::now();
        const double dt = std::chrono::duration<double>(now - last_poll_).count();
        last_poll_ = now;
        if (window_) {
            const WindowInput w = window_->poll(dt);
            if (w.quit) return false;
            for (std::size_t k = 0; k < 5; ++k)
                pending_.move[k] += w.move[k];
            pending_.action = pending_.action || w.action;
        } else if (report_.frames > 0) {
            pending_.move[3] += float(o_.turn_rate * dt);
            if (o_.action_each_second && now - last_action_ >= std::chrono::seconds(1)) {
                pending_.action = true;
                last_action_ = now;
            }
        }
        if (pending_.any() && (pending_.action || now - last_send_ >= kInputPeriod)) {
            input_.send(std::nullopt, pending_.move, pending_.action);
            pending_ = WindowInput{};
            last_send_ = now;
        }
        return true;
    }

    ClientReport finish() {
        report_.seconds = timer_.seconds();
        report_.latency = stats_.summary();
        if (!o_.contact_sheet.empty())
            if (Status s = sheet_.write(o_.contact_sheet); !s)
                spdlog::error("{}", s.error().message);
        return report_;
    }
    int frames() const { return report_.frames; }

private:
    using Clock = LatencyStats::Clock;
    static constexpr auto kInputPeriod = std::chrono::milliseconds(16);
    const ClientOptions& o_;
    std::map<uint64_t, Mat4> script_;
    LatencyStats& stats_;
    GameWindow* window_;
    InputSender input_;
    ContactSheet sheet_;
    std::unique_ptr<H264Decoder> video_;
    ClientReport report_;
    Timer timer_;
    Clock::time_point last_poll_ = Clock::now(), last_send_ = last_poll_, last_action_ = last_poll_;
    WindowInput pending_;
};

enum class LinkEnd { done, closed, lost };

// Shows frames until the client is done (frame count, window closed, stop), the coordinator
// closed the link, or the link was lost: a reset, a TLS stream cut short, or no frame for
// silence_seconds after frames had been coming (a half-open connection says nothing else).
LinkEnd play(const ClientOptions& o, FrameQueue& queue, ClientRun& run,
             const std::atomic<bool>& stop) {
    auto last_frame = std::chrono::steady_clock::now();
    const auto silence = std::chrono::duration<double>(o.silence_seconds);
    while (!stop && !queue.drained()) {
        if (auto bytes = queue.pop_for(std::chrono::milliseconds(4))) {
            last_frame = std::chrono::steady_clock::now();
            auto more = run.on_frame(*bytes);
            if (!more) {
                spdlog::error("{}", more.error().message);
                return LinkEnd::done;
            }
            if (!*more) return LinkEnd::done;
        }
        if (!run.poll()) return LinkEnd::done;
        if (run.frames() > 0 && o.silence_seconds > 0 &&
            std::chrono::steady_clock::now() - last_frame > silence) {
            queue.close(fmt::format("no frame for {} s", o.silence_seconds));
            return LinkEnd::lost;
        }
    }
    if (stop) return LinkEnd::done;
    return queue.reason() == net::kClosedByPeer ? LinkEnd::closed : LinkEnd::lost;
}

// Connects again, backing off, for up to reconnect_seconds; null when it gave up.
template <typename Connect>
std::shared_ptr<net::Session> reconnect(const ClientOptions& o, Connect& connect,
                                        const std::string& why, const std::atomic<bool>& stop) {
    if (o.reconnect_seconds <= 0) return nullptr;
    spdlog::warn("{}; reconnecting", why);
    const auto give_up = std::chrono::steady_clock::now() +
                         std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double>(o.reconnect_seconds));
    auto backoff = std::chrono::milliseconds(100);
    while (!stop && std::chrono::steady_clock::now() < give_up) {
        auto session = connect();
        if (session) {
            spdlog::info("reconnected");
            return *session;
        }
        spdlog::warn("{}; retrying in {} ms", session.error().message, backoff.count());
        std::this_thread::sleep_for(backoff);
        backoff = std::min(backoff * 2, std::chrono::milliseconds(2000));
    }
    spdlog::error("gave up reconnecting after {} s", o.reconnect_seconds);
    return nullptr;
}

Result<ClientReport> run_client(const ClientOptions& o, const std::atomic<bool>& stop) {
    std::map<uint64_t, Mat4> script;
    if (!o.script.empty()) {
        auto s = read_camera_script(o.script);
        if (!s) return s.error();
        script = std::move(*s);
    }
    if (!o.out_dir.empty())
        if (Status s = create_output_folder("--out", o.out_dir); !s) return s.error();
    LatencyStats stats;
    if (!o.latency_csv.empty())
        if (Status s = stats.open_csv(o.latency_csv); !s) return s.error();
    std::unique_ptr<GameWindow> window;
    if (o.window) {
        auto w = GameWindow::open("pathfarm");
        if (!w) return w.error();
        window = std::move(*w);
    }
    net::NetService net;
    net::ClientConfig config;
    config.host = o.host;
    config.port = o.port;
    config.secret = o.secret;
    config.tls = !o.insecure_plaintext;
    config.hello.role = net::PeerRole::client;
    config.hello.name = o.window ? "window-client" : "headless-client";
    config.hello.codecs = {codec_for(o.format)};
    std::shared_ptr<FrameQueue> queue;
    // Each connection has a queue of its own: a lost session's late callbacks cannot close
    // the next one's.
    const auto connect = [&]() {
        queue = std::make_shared<FrameQueue>();
        config.on_message = [q = queue](std::string&& m) { q->push(std::move(m)); };
        config.on_closed = [q = queue](const std::string& reason) { q->close(reason); };
        return net.connect_sync(config);
    };
    auto session = connect();
    if (!session) return session.error();
    ClientRun run(o, std::move(script), *session, stats, window.get());
    for (;;) {
        const LinkEnd end = play(o, *queue, run, stop);
        if (end != LinkEnd::lost) break;
        const std::string why = queue->reason();
        (*session)->close(why);
        auto again = reconnect(o, connect, why, stop);
        if (!again) break;
        session = std::move(again);
        run.reconnected(*session);
    }
    if (run.frames() == 0 && !stop)
        return make_error(ErrorCode::io_error, "no frames: {}", queue->reason());
    (*session)->close("client done");
    return run.finish();
}

}  // namespace pathfarm::client
