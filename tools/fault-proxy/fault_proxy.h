// A TCP fault proxy for integration tests and the soak benchmark (this kernel has no
// sch_netem; the command-line form is pathfarm-fault-proxy): it relays each
// connection accepted on its own port to a target port on loopback and injects faults on
// request: added latency, a bandwidth cap, a stall of all traffic, a reset in the middle of a
// message (after a number of bytes, the connection is cut with RST both ways), and a
// half-open connection (forwarding stops, the sockets stay open: neither end hears a FIN).
// One thread per connection, blocking sockets and poll; thread-safe controls.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <list>
#include <mutex>
#include <string>
#include <thread>

namespace pathfarm::tools {

class FaultProxy {
public:
    enum class Direction { to_target, from_target };

    // listen_port 0: an ephemeral port (port() tells which).
    explicit FaultProxy(uint16_t target_port, uint16_t listen_port = 0);
    ~FaultProxy();
    FaultProxy(const FaultProxy&) = delete;
    FaultProxy& operator=(const FaultProxy&) = delete;

    uint16_t port() const { return port_; }
    int connections() const { return accepted_; }
    // Bytes forwarded so far over all connections, per direction.
    uint64_t forwarded(Direction d) const { return forwarded_[int(d)]; }

    // Applies to every connection, from now on.
    void set_latency(std::chrono::milliseconds one_way) { latency_ms_ = int(one_way.count()); }
    void set_bandwidth(uint64_t bytes_per_second) { bandwidth_ = bytes_per_second; }
    // Nothing is forwarded either way until `duration` has passed.
    void stall(std::chrono::milliseconds duration);
    // The next `bytes` bytes in `d` still pass; then the connections open at that moment are
    // reset (the byte count lands in the middle of a message for any message longer).
    void reset_after(uint64_t bytes, Direction d);
    // Forwarding stops for good on the connections open now; their sockets stay open.
    void half_open();
    // Keeps a copy of every byte forwarded from now on (tests check what crosses the wire).
    void capture() { capturing_ = true; }
    std::string captured(Direction d) const;

private:
    struct Link;
    void accept_loop();
    void pump(Link& link);
    void forwarded(int dir, const std::string& bytes, std::size_t n);

    uint16_t target_port_;
    uint16_t port_ = 0;
    int listen_fd_ = -1;
    std::atomic<bool> stop_{false};
    std::atomic<int> accepted_{0};
    std::atomic<uint64_t> forwarded_[2] = {0, 0};
    std::atomic<int> latency_ms_{0};
    std::atomic<uint64_t> bandwidth_{0};
    std::atomic<int64_t> stalled_until_ns_{0};
    std::atomic<int64_t> reset_at_[2] = {-1, -1};  // a forwarded_ count; -1: none
    std::atomic<uint64_t> half_open_epoch_{0};
    std::atomic<bool> capturing_{false};
    mutable std::mutex mutex_;  // links_, captured_
    std::string captured_[2];
    std::list<Link> links_;
    std::thread acceptor_;
};

}  // namespace pathfarm::tools
