// Headless client: frames arrive on the network thread and are written from this one.
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
#include "common/base/timer.h"
#include "common/film/float_codec.h"
#include "common/film/image_io.h"
#include "common/math/transform.h"
#include "common/net/framing.h"
#include "common/net/session.h"
#include "pathfarm/wire/v1/envelope.pb.h"

namespace pathfarm::client {
namespace {

namespace pb = ::pathfarm::wire::v1;

float srgb_to_linear_byte(uint8_t v) {
    const float x = float(v) / 255.0f;
    return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

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
    std::optional<std::string> pop(const std::atomic<bool>& stop) {
        std::unique_lock lock(mutex_);
        while (frames_.empty() && !closed_ && !stop)
            cv_.wait_for(lock, std::chrono::milliseconds(100));
        if (frames_.empty()) return std::nullopt;
        std::string m = std::move(frames_.front());
        frames_.pop_front();
        return m;
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

// Decodes a frame to linear float (PNG frames are decoded from sRGB).
Result<FloatImage> decode_frame(const pb::EncodedFrame& f) {
    FloatImage img(int(f.width()), int(f.height()));
    if (f.codec() == pb::FRAME_CODEC_FLOAT_ZSTD) {
        auto rgb = decompress_floats(f.data(), std::size_t(f.width()) * f.height() * 3);
        if (!rgb) return rgb.error();
        img.rgb = std::move(*rgb);
        return img;
    }
    if (f.codec() != pb::FRAME_CODEC_PNG)
        return make_error(ErrorCode::unsupported, "frame {}: codec {} not supported", f.frame(),
                          int(f.codec()));
    auto png = decode_rgba8(reinterpret_cast<const unsigned char*>(f.data().data()),
                            f.data().size(), "frame.png");
    if (!png) return png.error();
    if (png->width != img.width || png->height != img.height)
        return make_error(ErrorCode::parse_error, "frame {}: PNG is {}x{}, frame {}x{}", f.frame(),
                          png->width, png->height, img.width, img.height);
    for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i)
        for (int c = 0; c < 3; ++c)
            img.rgb[i * 3 + c] = srgb_to_linear_byte(png->rgba[i * 4 + c]);
    return img;
}

Status write_frame(const ClientOptions& o, const pb::EncodedFrame& f, const FloatImage& img) {
    if (o.out_dir.empty()) return {};
    const std::string base = fmt::format("{}/frame_{:06d}", o.out_dir, f.frame());
    if (f.codec() == pb::FRAME_CODEC_PNG) {  // keep the coordinator's bytes
        std::ofstream(base + ".png", std::ios::binary) << f.data();
        return {};
    }
    return write_image(base + ".exr", img);
}

void send_pose(net::Session& s, uint64_t sequence, const Mat4& pose) {
    pb::Envelope e;
    e.set_version(net::kProtocolVersion);
    auto* in = e.mutable_input();
    in->set_sequence(sequence);
    in->set_timestamp_us(uint64_t(std::chrono::duration_cast<std::chrono::microseconds>(
                                      std::chrono::steady_clock::now().time_since_epoch())
                                      .count()));
    in->set_camera_to_world(std::string(reinterpret_cast<const char*>(&pose[0][0]), sizeof(Mat4)));
    s.send(e.SerializeAsString());
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
    std::map<uint64_t, Mat4> script;
    if (!o.script.empty()) {
        auto s = read_camera_script(o.script);
        if (!s) return s.error();
        script = std::move(*s);
    }
    if (!o.out_dir.empty()) std::filesystem::create_directories(o.out_dir);
    net::NetService net;
    auto queue = std::make_shared<FrameQueue>();
    net::ClientConfig config;
    config.host = o.host;
    config.port = o.port;
    config.secret = o.secret;
    config.hello.role = net::PeerRole::client;
    config.hello.name = "headless-client";
    config.hello.codecs = {o.format == OutputFormat::exr ? int(pb::FRAME_CODEC_FLOAT_ZSTD)
                                                         : int(pb::FRAME_CODEC_PNG)};
    config.on_message = [queue](std::string&& m) { queue->push(std::move(m)); };
    config.on_closed = [queue](const std::string& reason) { queue->close(reason); };
    auto session = net.connect_sync(config);
    if (!session) return session.error();
    if (auto first = script.find(0); first != script.end()) send_pose(**session, 1, first->second);
    ClientReport report;
    ContactSheet sheet(o.frames > 0 ? (o.frames + 15) / 16 : 1);
    Timer timer;
    uint64_t sequence = 1;
    while (auto bytes = queue->pop(stop)) {
        pb::Envelope e;
        if (!e.ParseFromString(*bytes) || !e.has_frame()) continue;
        if (report.frames == 0) timer.reset();  // frame rate between frames, not connection time
        auto image = decode_frame(e.frame());
        if (!image) {
            spdlog::error("{}", image.error().message);
            continue;
        }
        if (Status s = write_frame(o, e.frame(), *image); !s)
            spdlog::error("{}", s.error().message);
        sheet.add(uint64_t(report.frames), *image);
        ++report.frames;
        if (auto next = script.find(e.frame().frame() + 1); next != script.end())
            send_pose(**session, ++sequence, next->second);
        if (o.frames > 0 && report.frames >= o.frames) break;
    }
    report.seconds = timer.seconds();
    if (!o.contact_sheet.empty())
        if (Status s = sheet.write(o.contact_sheet); !s) spdlog::error("{}", s.error().message);
    if (report.frames == 0 && !stop)
        return make_error(ErrorCode::io_error, "no frames: {}", queue->reason());
    (*session)->close("client done");
    return report;
}

}  // namespace pathfarm::client
