// Clients: inputs in, encoded frames out.
#include "coordinator/session/client_hub.h"

#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "common/wire/messages.h"

namespace pathfarm::coord {

PlayerInput bounded_input(const wire::Input& in) {
    PlayerInput input;
    input.sequence = in.sequence;
    input.action = in.action;
    input.camera_to_world = in.camera_to_world;  // decode_input keeps finite poses only
    for (std::size_t k = 0; k < std::min<std::size_t>(in.move.size(), input.move.size()); ++k) {
        const float limit = k < 3 ? 10.0f : 3.14159265f;
        input.move[k] = std::isfinite(in.move[k]) ? std::clamp(in.move[k], -limit, limit) : 0.0f;
    }
    return input;
}

void ClientHub::add(std::shared_ptr<net::Session> s) {
    const uint64_t id = s->peer().session_id;
    s->on_message = [this, id](std::string&& m) { on_input(id, m); };
    s->on_closed = [this, id](const std::string& reason) {
        spdlog::info("client {} left: {}", id, reason);
        std::lock_guard lock(mutex_);
        clients_.erase(id);
    };
    std::lock_guard lock(mutex_);
    if (!accepting_) return s->close("coordinator finishing");
    clients_[id] = Client{s, choose_codec(s->peer().codecs)};
}

void ClientHub::on_input(uint64_t id, const std::string& bytes) {
    auto in = wire::decode_input(bytes);
    std::lock_guard lock(mutex_);
    const auto it = clients_.find(id);
    if (it == clients_.end()) return;
    if (!in) return it->second.session->reject(net::ProtocolError::malformed, in.error().message);
    pending_.push_back(bounded_input(*in));
}

std::vector<PlayerInput> ClientHub::take_inputs() {
    std::lock_guard lock(mutex_);
    return std::exchange(pending_, {});
}

std::size_t ClientHub::size() const {
    std::lock_guard lock(mutex_);
    return clients_.size();
}

void ClientHub::send(const FloatImage& image, uint64_t frame, uint64_t last_input_sequence) {
    std::vector<std::pair<std::shared_ptr<net::Session>, FrameCodec>> targets;
    {
        std::lock_guard lock(mutex_);
        for (const auto& [id, c] : clients_)
            targets.emplace_back(c.session, c.codec);
    }
    std::map<FrameCodec, std::string> encoded;  // outside the lock: encoding takes milliseconds
    for (auto& [session, codec] : targets) {
        if (!encoded.count(codec)) {
            auto bytes = encode_frame(image, codec, jpeg_quality_);
            if (!bytes) {
                spdlog::error("frame {}: {}", frame, bytes.error().message);
                continue;
            }
            encoded[codec] =
                wire::encode_frame({frame, uint32_t(image.width), uint32_t(image.height), codec,
                                    std::move(*bytes), last_input_sequence});
        }
        session->send(encoded[codec]);
    }
}

std::vector<std::shared_ptr<net::Session>> ClientHub::stop_accepting() {
    std::lock_guard lock(mutex_);
    accepting_ = false;
    std::vector<std::shared_ptr<net::Session>> sessions;
    for (auto& [id, c] : clients_)
        sessions.push_back(c.session);
    clients_.clear();
    return sessions;
}

}  // namespace pathfarm::coord
