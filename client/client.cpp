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
#include "common/film/image_io.h"
#include "common/film/jpeg_codec.h"
#include "common/film/tonemap.h"
#include "common/math/transform.h"
#include "common/net/framing.h"
#include "common/net/session.h"
#include "pathfarm/wire/v1/envelope.pb.h"

namespace pathfarm::client {
namespace {

namespace pb = ::pathfarm::wire::v1;

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

Result<DecodedFrame> decode_frame(const pb::EncodedFrame& f) {
    DecodedFrame d{int(f.width()), int(f.height()), {}, {}};
    if (d.width <= 0 || d.height <= 0 || d.width > 16384 || d.height > 16384)
        return make_error(ErrorCode::parse_error, "frame {}: size {}x{}", f.frame(), d.width,
                          d.height);
    if (f.codec() == pb::FRAME_CODEC_FLOAT_ZSTD) {
        auto rgb = decompress_floats(f.data(), std::size_t(d.width) * d.height * 3);
        if (!rgb) return rgb.error();
        d.linear = FloatImage(d.width, d.height);
        d.linear->rgb = std::move(*rgb);
        d.srgb8 = tonemap_to_srgb8(*d.linear);
        return d;
    }
    int w = 0, h = 0;
    if (f.codec() == pb::FRAME_CODEC_JPEG) {
        auto jpeg = decode_jpeg(f.data());
        if (!jpeg) return jpeg.error();
        w = jpeg->width;
        h = jpeg->height;
        d.srgb8 = std::move(jpeg->rgb);
    } else if (f.codec() == pb::FRAME_CODEC_PNG) {
        auto png = decode_rgba8(reinterpret_cast<const unsigned char*>(f.data().data()),
                                f.data().size(), "frame.png");
        if (!png) return png.error();
        w = png->width;
        h = png->height;
        d.srgb8.resize(std::size_t(w) * h * 3);
        for (std::size_t i = 0; i < std::size_t(w) * h; ++i)
            for (int c = 0; c < 3; ++c)
                d.srgb8[i * 3 + c] = png->rgba[i * 4 + c];
    } else {
        return make_error(ErrorCode::unsupported, "frame {}: codec {} not supported", f.frame(),
                          int(f.codec()));
    }
    if (w != d.width || h != d.height)
        return make_error(ErrorCode::parse_error, "frame {}: image is {}x{}, frame {}x{}",
                          f.frame(), w, h, d.width, d.height);
    return d;
}

Status write_frame(const ClientOptions& o, const pb::EncodedFrame& f, const DecodedFrame& d) {
    if (o.out_dir.empty()) return {};
    const std::string base = fmt::format("{}/frame_{:06d}", o.out_dir, f.frame());
    if (d.linear) return write_image(base + ".exr", *d.linear);
    // Keep the coordinator's bytes.
    std::ofstream(base + (f.codec() == pb::FRAME_CODEC_PNG ? ".png" : ".jpg"), std::ios::binary)
        << f.data();
    return {};
}

class InputSender {
public:
    InputSender(net::Session& session, LatencyStats& stats) : session_(session), stats_(stats) {}

    void send(const std::optional<Mat4>& pose, const std::array<float, 5>& move, bool action) {
        pb::Envelope e;
        e.set_version(net::kProtocolVersion);
        auto* in = e.mutable_input();
        const auto now = LatencyStats::Clock::now();
        in->set_sequence(++sequence_);
        in->set_timestamp_us(uint64_t(
            std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count()));
        if (pose)
            in->set_camera_to_world(
                std::string(reinterpret_cast<const char*>(&(*pose)[0][0]), sizeof(Mat4)));
        if (move != std::array<float, 5>{})
            for (float m : move)
                in->add_move(m);
        in->set_action(action);
        stats_.input_sent(sequence_, now);
        session_.send(e.SerializeAsString());
    }

private:
    net::Session& session_;
    LatencyStats& stats_;
    uint64_t sequence_ = 0;
};

int codec_for(OutputFormat f) {
    switch (f) {
        case OutputFormat::exr:
            return int(pb::FRAME_CODEC_FLOAT_ZSTD);
        case OutputFormat::png:
            return int(pb::FRAME_CODEC_PNG);
        case OutputFormat::jpeg:
            break;
    }
    return int(pb::FRAME_CODEC_JPEG);
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

Result<ClientReport> run_client(const ClientOptions& o, const std::atomic<bool>& stop) {
    using Clock = LatencyStats::Clock;
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
    config.hello.role = net::PeerRole::client;
    config.hello.name = o.window ? "window-client" : "headless-client";
    config.hello.codecs = {codec_for(o.format)};
    config.on_message = [queue](std::string&& m) { queue->push(std::move(m)); };
    config.on_closed = [queue](const std::string& reason) { queue->close(reason); };
    auto session = net.connect_sync(config);
    if (!session) return session.error();
    InputSender input(**session, stats);
    if (auto first = script.find(0); first != script.end()) input.send(first->second, {}, false);
    ClientReport report;
    ContactSheet sheet(o.frames > 0 ? (o.frames + 15) / 16 : 1);
    Timer timer;
    // Input is gathered continuously and sent at most every 16 ms (and with every action).
    constexpr auto kInputPeriod = std::chrono::milliseconds(16);
    Clock::time_point last_poll = Clock::now(), last_send = last_poll, last_action = last_poll;
    WindowInput pending;
    while (!stop && !queue->drained()) {
        if (auto bytes = queue->pop_for(std::chrono::milliseconds(4))) {
            pb::Envelope e;
            if (!e.ParseFromString(*bytes) || !e.has_frame()) continue;
            const pb::EncodedFrame& f = e.frame();
            stats.frame_arrived(f.frame(), f.last_input_sequence(), Clock::now());
            if (report.frames == 0) timer.reset();  // between frames, not connection time
            auto frame = decode_frame(f);
            if (!frame) {
                spdlog::error("{}", frame.error().message);
                continue;
            }
            if (Status s = write_frame(o, f, *frame); !s) spdlog::error("{}", s.error().message);
            if (window) {
                if (Status s = window->show(frame->width, frame->height, frame->srgb8); !s)
                    return s.error();
                if (report.frames + 1 == o.screenshot_frame && !o.screenshot.empty())
                    if (Status s = window->screenshot(o.screenshot); !s) return s.error();
            }
            sheet.add(uint64_t(report.frames), frame->width, frame->height, frame->srgb8);
            ++report.frames;
            if (auto next = script.find(f.frame() + 1); next != script.end())
                input.send(next->second, {}, false);
            if (o.frames > 0 && report.frames >= o.frames) break;
        }
        const auto now = Clock::now();
        const double dt = std::chrono::duration<double>(now - last_poll).count();
        last_poll = now;
        if (window) {
            const WindowInput w = window->poll(dt);
            if (w.quit) break;
            for (std::size_t k = 0; k < 5; ++k)
                pending.move[k] += w.move[k];
            pending.action = pending.action || w.action;
        } else if (report.frames > 0) {  // a scripted player: turns, and acts once a second
            pending.move[3] += float(o.turn_rate * dt);
            if (o.action_each_second && now - last_action >= std::chrono::seconds(1)) {
                pending.action = true;
                last_action = now;
            }
        }
        if (pending.any() && (pending.action || now - last_send >= kInputPeriod)) {
            input.send(std::nullopt, pending.move, pending.action);
            pending = WindowInput{};
            last_send = now;
        }
    }
    report.seconds = timer.seconds();
    report.latency = stats.summary();
    if (!o.contact_sheet.empty())
        if (Status s = sheet.write(o.contact_sheet); !s) spdlog::error("{}", s.error().message);
    if (report.frames == 0 && !stop)
        return make_error(ErrorCode::io_error, "no frames: {}", queue->reason());
    (*session)->close("client done");
    return report;
}

}  // namespace pathfarm::client
