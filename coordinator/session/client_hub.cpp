// Clients: inputs in, encoded frames out.
#include "coordinator/session/client_hub.h"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "common/wire/messages.h"
#include "coordinator/frame/parallel_image.h"
#include "coordinator/http/web_port.h"
#include "coordinator/http/web_protocol.h"

namespace pathfarm::coord {
namespace {

PlayerInput player_input(const wire::Input& in) {
    PlayerInput input;
    input.sequence = in.sequence;
    input.action = in.action;
    input.camera_to_world = in.camera_to_world;  // decode_input keeps finite poses only
    for (std::size_t k = 0; k < std::min<std::size_t>(in.move.size(), input.move.size()); ++k)
        input.move[k] = in.move[k];
    return bounded_input(input);
}

uint16_t clamp16(int v) { return uint16_t(std::clamp(v, 0, 65535)); }

}  // namespace

void ClientHub::add(std::shared_ptr<net::Session> s) {
    const uint64_t id = s->peer().session_id & ~kBrowserBit;
    s->on_message = [this, id](std::string&& m) { on_input(id, m); };
    s->on_closed = [this, id](const std::string& reason) {
        spdlog::info("client {} left: {}", id, reason);
        std::lock_guard lock(mutex_);
        clients_.erase(id);
        count_clients_locked();
    };
    std::lock_guard lock(mutex_);
    if (!accepting_) return s->close("coordinator finishing");
    const FrameCodec codec = choose_codec(s->peer().codecs);
    clients_[id] = Client{s, codec, codec == FrameCodec::h264, true, std::nullopt};
    count_clients_locked();
}

void ClientHub::browser_joined(uint64_t id, bool h264) {
    std::lock_guard lock(mutex_);
    if (!accepting_) return;
    clients_[id | kBrowserBit] = Client{nullptr, FrameCodec::jpeg, h264, true, std::nullopt};
    count_clients_locked();
}

void ClientHub::browser_needs_key(uint64_t id) {
    std::lock_guard lock(mutex_);
    if (const auto it = clients_.find(id | kBrowserBit); it != clients_.end())
        it->second.needs_key = true;
}

void ClientHub::browser_left(uint64_t id) {
    std::lock_guard lock(mutex_);
    clients_.erase(id | kBrowserBit);
    count_clients_locked();
}

void ClientHub::browser_input(uint64_t id, const PlayerInput& input) {
    queue_input(id | kBrowserBit, input);
}

void ClientHub::on_input(uint64_t id, const std::string& bytes) {
    auto in = wire::decode_input(bytes);
    if (!in) {
        std::lock_guard lock(mutex_);
        const auto it = clients_.find(id);
        if (it != clients_.end())
            it->second.session->reject(net::ProtocolError::malformed, in.error().message);
        return;
    }
    queue_input(id, player_input(*in));
}

void ClientHub::queue_input(uint64_t key, const PlayerInput& input) {
    std::lock_guard lock(mutex_);
    if (clients_.count(key)) pending_.push_back({key, input, Clock::now()});
}

void ClientHub::count_clients_locked() {
    std::size_t browsers = 0;
    for (const auto& [key, c] : clients_)
        browsers += (key & kBrowserBit) ? 1 : 0;
    metrics_.set_clients(clients_.size() - browsers, browsers);
}

std::vector<PlayerInput> ClientHub::take_inputs(uint64_t frame) {
    std::lock_guard lock(mutex_);
    FrameInputs taken{frame, {}, {}};
    std::vector<PlayerInput> inputs;
    for (Pending& p : pending_) {
        uint64_t& newest = applied_[p.client];
        newest = std::max(newest, p.input.sequence);
        taken.received.push_back(p.received);
        inputs.push_back(std::move(p.input));
    }
    pending_.clear();
    taken.newest = applied_;
    frames_.push_back(std::move(taken));
    return inputs;
}

// The inputs `frame` applied; frames are shown in the order they were prepared.
ClientHub::FrameInputs ClientHub::inputs_of(uint64_t frame) {
    std::lock_guard lock(mutex_);
    while (!frames_.empty() && frames_.front().frame < frame)
        frames_.pop_front();
    if (frames_.empty() || frames_.front().frame != frame) return {frame, applied_, {}};
    FrameInputs f = std::move(frames_.front());
    frames_.pop_front();
    return f;
}

std::size_t ClientHub::size() const {
    std::lock_guard lock(mutex_);
    return clients_.size();
}

std::optional<H264Picture> ClientHub::encode_h264(const FloatImage& image, bool key) {
    if (h264_failed_) return std::nullopt;
    if (!h264_ || h264_->settings().width != image.width ||
        h264_->settings().height != image.height) {
        auto opened = H264Encoder::open(h264_stream_settings(image.width, image.height));
        if (!opened) {
            spdlog::error("{}: browsers get JPEG", opened.error().message);
            h264_failed_ = true;
            return std::nullopt;
        }
        h264_ = std::move(*opened);
        key = true;
    }
    auto picture = h264_->encode(tonemap_to_srgb8_parallel(image), key);
    if (!picture) {
        spdlog::error("{}", picture.error().message);
        return std::nullopt;
    }
    return std::move(*picture);
}

void ClientHub::send_to_browser(uint64_t key, const Client& c, const std::string& jpeg,
                                const std::optional<H264Picture>& video, const ShownFrame& shown,
                                uint64_t echo, std::size_t& bytes) {
    const bool h264 = c.h264 && video;
    if (h264 && c.needs_key && !video->key) return;  // not decodable for it
    WebFrameHeader header{h264 ? WebCodec::h264 : WebCodec::jpeg,
                          !h264 || video->key,
                          clamp16(shown.width),
                          clamp16(shown.height),
                          clamp16(shown.render_width),
                          clamp16(shown.render_height),
                          clamp16(shown.spp),
                          shown.frame,
                          echo,
                          web_->clock_us()};
    auto message =
        std::make_shared<const std::string>(encode_web_frame(header, h264 ? video->bytes : jpeg));
    bytes += message->size();
    const MessageKind kind = !h264        ? MessageKind::independent
                             : video->key ? MessageKind::key
                                          : MessageKind::delta;
    web_->send(key & ~kBrowserBit, std::move(message), kind);
}

void ClientHub::send(const FloatImage& image, const ShownFrame& shown) {
    const FrameInputs applied = inputs_of(shown.frame);
    std::vector<std::pair<uint64_t, Client>> targets;
    bool h264 = false, key = false;
    {
        std::lock_guard lock(mutex_);
        targets.assign(clients_.begin(), clients_.end());
        for (auto& [id, c] : clients_) {
            h264 = h264 || c.h264;
            key = key || (c.h264 && c.needs_key);
        }
    }
    const auto echo = [&](uint64_t id) {  // the newest of its inputs the frame applied
        return applied.newest.count(id) != 0 ? applied.newest.at(id) : uint64_t(0);
    };
    // Outside the lock: encoding takes milliseconds.
    const std::optional<H264Picture> video = h264 ? encode_h264(image, key) : std::nullopt;
    std::map<FrameCodec, std::string> pictures;
    std::size_t bytes = 0;
    std::vector<uint64_t> sent, backed_up;
    ShownFrame sized = shown;
    sized.width = image.width;
    sized.height = image.height;
    for (auto& [id, c] : targets) {
        const bool as_video = c.h264 && video;
        if (c.session && c.h264 && !video) continue;  // a native H.264 client takes nothing else
        if (!as_video && !pictures.count(c.codec)) {
            auto encoded = encode_frame(image, c.codec, jpeg_quality_);
            if (!encoded) {
                spdlog::error("frame {}: {}", shown.frame, encoded.error().message);
                continue;
            }
            pictures[c.codec] = std::move(*encoded);
        }
        if (c.session) {
            if (as_video && c.needs_key && !video->key) continue;
            const bool taken =
                send_native(c,
                            wire::encode_frame(
                                {shown.frame, uint32_t(image.width), uint32_t(image.height),
                                 c.codec, as_video ? video->bytes : pictures[c.codec], echo(id)}),
                            bytes);
            (taken ? sent : backed_up).push_back(id);
        } else if (web_) {
            send_to_browser(id, c, pictures[c.codec], video, sized, echo(id), bytes);
            sent.push_back(id);  // the web port drops and asks for keys on its own
        }
    }
    if (video && video->key) {  // those that were sent it (not those that joined since)
        std::lock_guard lock(mutex_);
        for (const uint64_t id : sent)
            if (const auto it = clients_.find(id); it != clients_.end() && it->second.h264)
                it->second.needs_key = false;
    }
    note_backlogs(sent, backed_up);
    metrics_.add_client_bytes(bytes);
    const auto now = Clock::now();
    for (const Clock::time_point at : applied.received)
        metrics_.observe_input_latency(std::chrono::duration<double>(now - at).count());
}

// A client that has not taken its last frames skips this one: a queue is latency, and one
// that never reads (a half-open link) must not hold frames forever.
bool ClientHub::send_native(const Client& c, std::string message, std::size_t& bytes) {
    if (c.session->unsent_bytes() > std::max(kMinUnsentLimit, 2 * message.size())) return false;
    bytes += message.size();
    c.session->send(std::move(message));
    return true;
}

// A native client that skipped a frame needs a key picture next (H.264); one that has not
// caught up for kBackedUpLimit is closed (it reconnects if it is alive).
void ClientHub::note_backlogs(const std::vector<uint64_t>& sent,
                              const std::vector<uint64_t>& backed_up) {
    std::lock_guard lock(mutex_);
    for (const uint64_t id : sent)
        if (const auto it = clients_.find(id); it != clients_.end())
            it->second.backed_up_since.reset();
    const auto now = Clock::now();
    for (const uint64_t id : backed_up) {
        const auto it = clients_.find(id);
        if (it == clients_.end()) continue;
        Client& c = it->second;
        c.needs_key = c.h264;
        if (!c.backed_up_since) c.backed_up_since = now;
        if (now - *c.backed_up_since < kBackedUpLimit) continue;
        spdlog::warn("client \"{}\" took no frame for {} s; disconnecting it",
                     c.session->peer().name,
                     std::chrono::duration_cast<std::chrono::seconds>(kBackedUpLimit).count());
        c.session->close("not reading its frames");
        clients_.erase(it);
        count_clients_locked();
    }
}

std::vector<std::shared_ptr<net::Session>> ClientHub::stop_accepting() {
    std::lock_guard lock(mutex_);
    accepting_ = false;
    std::vector<std::shared_ptr<net::Session>> sessions;
    for (auto& [id, c] : clients_)
        if (c.session) sessions.push_back(c.session);
    clients_.clear();
    count_clients_locked();
    return sessions;
}

}  // namespace pathfarm::coord
