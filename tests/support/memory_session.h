// An in-memory net::Session for socket-free tests of the coordinator's tracer pool and client
// hub: it records what is sent to the peer, and the test delivers the peer's messages and its
// leaving through the handlers the code under test installed.
#pragma once

#include <atomic>
#include <mutex>
#include <string>
#include <vector>

#include "common/net/session.h"

namespace pathfarm::test {

class MemorySession final : public net::Session {
public:
    MemorySession(uint64_t id, std::string name, bool wants_bvh = false) {
        peer_.session_id = id;
        peer_.name = std::move(name);
        peer_.wants_bvh_nodes = wants_bvh;
    }
    void send(std::string envelope) override {
        std::lock_guard lock(mutex_);
        if (open_) sent_.push_back(std::move(envelope));
    }
    void reject(net::ProtocolError code, std::string message) override {
        {
            std::lock_guard lock(mutex_);
            rejection_ = std::to_string(int(code)) + ": " + message;
        }
        close(std::move(message));
    }
    void close(std::string reason) override {
        std::lock_guard lock(mutex_);
        open_ = false;
        close_reason_ = std::move(reason);
    }
    bool open() const override {
        std::lock_guard lock(mutex_);
        return open_;
    }
    const net::PeerInfo& peer() const override { return peer_; }
    std::size_t unsent_bytes() const override { return unsent; }
    void set_codecs(std::vector<int> codecs) { peer_.codecs = std::move(codecs); }

    std::atomic<std::size_t> unsent{0};  // what unsent_bytes() reports (a peer not reading)

    // The peer sends `envelope` / the peer goes away (as the network thread reports them).
    void deliver(const std::string& envelope) { on_message(std::string(envelope)); }
    void leave(const std::string& reason) { on_closed(reason); }

    // What was sent to the peer since the last call.
    std::vector<std::string> take_sent() {
        std::lock_guard lock(mutex_);
        return std::exchange(sent_, {});
    }
    std::string rejection() const {
        std::lock_guard lock(mutex_);
        return rejection_;
    }

private:
    net::PeerInfo peer_;
    mutable std::mutex mutex_;
    std::vector<std::string> sent_;
    bool open_ = true;
    std::string close_reason_, rejection_;
};

}  // namespace pathfarm::test
