// The client loop: frames arrive on the network thread; this thread decodes, shows or
// writes them, and gathers and sends input.
#include "client/client.h"

#include <cmath>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>

#include <spdlog/spdlog.h>

#include "client/contact_sheet.h"
#include "client/game_window.h"
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

// A frame ready to show (sRGB bytes) and, for lossless float frames, its linear pixels.
struct DecodedFrame {
    int width = 0, height = 0;
    std::vector<uint8_t> srgb8;
    std::optional<FloatImage> linear;
};

// `video`: the H.264 stream's decoder (each picture depends on the ones before).
Result<DecodedFrame> decode_image(const wire::EncodedFrame& f, H264Decoder& video) {
    DecodedFrame d{int(f.width), int(f.height), {}, {}};  // sizes checked by wire::decode_frame
    if (f.codec == wire::FrameCodec::float_zstd) {
        auto rgb = decompress_floats(f.data, std::size_t(d.width) * d.height * 3);
        if (!rgb) return rgb.error();
        d.linear = FloatImage(d.width, d.height);
        d.linear->rgb = std::move(*rgb);
        d.srgb8 = tonemap_to_srgb8(*d.linear);
        return d;
    }
    int w = 0, h = 0;
    if (f.codec == wire::FrameCodec::h264) {
        auto picture = video.decode(f.data);
        if (!picture)
            return make_error(ErrorCode::parse_error, "frame {}: {}", f.frame,
                              picture.error().message);
        w = picture->width;
        h = picture->height;
        d.srgb8 = std::move(picture->rgb);
    } else if (f.codec == wire::FrameCodec::jpeg) {
        auto jpeg = decode_jpeg(f.data);
        if (!jpeg) return jpeg.error();
        w = jpeg->width;
        h = jpeg->height;
        d.srgb8 = std::move(jpeg->rgb);
    } else {  // png
        auto png = decode_rgba8(reinterpret_cast<const unsigned char*>(f.data.data()),
                                f.data.size(), "frame.png");
        if (!png) return png.error();
        w = png->width;
        h = png->height;
        d.srgb8.resize(std::size_t(w) * h * 3);
        for (std::size_t i = 0; i < std::size_t(w) * h; ++i)
            for (int c = 0; c < 3; ++c)
                d.srgb8[i * 3 + c] = png->rgba[i * 4 + c];
    }
    if (w != d.width || h != d.height)
        return make_error(ErrorCode::parse_error, "frame {}: image is {}x{}, frame {}x{}", f.frame,
                          w, h, d.width, d.height);
    return d;
}

Status write_frame(const ClientOptions& o, const wire::EncodedFrame& f, const DecodedFrame& d) {
    if (o.out_dir.empty()) return {};
    const std::string base = fmt::format("{}/frame_{:06d}", o.out_dir, f.frame);
    if (d.linear) return write_image(base + ".exr", *d.linear);
    if (f.codec == wire::FrameCodec::h264) {  // the frame as shown, and the playable stream
        std::ofstream(o.out_dir + "/stream.h264", std::ios::binary | std::ios::app) << f.data;
        auto png = encode_png(d.width, d.height, d.srgb8);
        if (!png) return png.error();
        std::ofstream(base + ".png", std::ios::binary)
            .write(reinterpret_cast<const char*>(png->data()), std::streamsize(png->size()));
        return {};
    }
    // Keep the coordinator's bytes.
    std::ofstream(base + (f.codec == wire::FrameCodec::png ? ".png" : ".jpg"), std::ios::binary)
        << f.data;
    return {};
}

class InputSender {
public:
    InputSender(net::Session& session, LatencyStats& stats) : session_(session), stats_(stats) {}

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
        session_.send(wire::encode_input(in));
    }

private:
    net::Session& session_;
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
    ClientRun(const ClientOptions& o, std::map<uint64_t, Mat4> script, net::Session& session,
              LatencyStats& stats, GameWindow* window)
        : o_(o),
          script_(std::move(script)),
          stats_(stats),
          window_(window),
          input_(session, stats),
          sheet_(o.frames > 0 ? (o.frames + 15) / 16 : 1) {
        if (auto first = script_.find(0); first != script_.end())
            input_.send(first->second, {}, false);
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

Result<ClientReport> run_client(const ClientOptions& o, const std::atomic<bool>& stop) {
    std::map<uint64_t, Mat4> script;
    if (!o.script.empty()) {
        auto s = read_camera_script(o.script);
        if (!s) return s.error();
        script = std::move(*s);
    }
    if (!o.out_dir.empty()) std::filesystem::create_directories(o.out_dir);
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
    auto queue = std::make_shared<FrameQueue>();
    net::ClientConfig config;
    config.host = o.host;
    config.port = o.port;
    config.secret = o.secret;
    config.tls = !o.insecure_plaintext;
    config.hello.role = net::PeerRole::client;
    config.hello.name = o.window ? "window-client" : "headless-client";
    config.hello.codecs = {codec_for(o.format)};
    config.on_message = [queue](std::string&& m) { queue->push(std::move(m)); };
    config.on_closed = [queue](const std::string& reason) { queue->close(reason); };
    auto session = net.connect_sync(config);
    if (!session) return session.error();
    ClientRun run(o, std::move(script), **session, stats, window.get());
    while (!stop && !queue->drained()) {
        if (auto bytes = queue->pop_for(std::chrono::milliseconds(4))) {
            auto more = run.on_frame(*bytes);
            if (!more) return more.error();
            if (!*more) break;
        }
        if (!run.poll()) break;
    }
    if (run.frames() == 0 && !stop)
        return make_error(ErrorCode::io_error, "no frames: {}", queue->reason());
    (*session)->close("client done");
    return run.finish();
}

}  // namespace pathfarm::client
