// Authenticated message sessions over TCP (DESIGN.md, "Protocol"). NetService owns the network
// thread; every connection is TLS 1.3 keyed by the farm secret (tls_psk.h; plaintext only when
// both ends are told --insecure-plaintext) and starts with the handshake (version, role,
// capabilities, HMAC challenge-response both ways) and only then becomes a Session that carries
// serialised Envelopes. A peer that sends something malformed, oversized, out of order or
// unauthenticated gets an Error envelope and is disconnected; nothing else is affected.
// Asio stays inside session.cpp, protobuf inside handshake.cpp.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/base/result.h"

namespace pathfarm::net {

enum class PeerRole : uint8_t { tracer, client };
const char* role_name(PeerRole role);

// What a peer announced in its Hello.
struct PeerInfo {
    PeerRole role = PeerRole::tracer;
    std::string name;
    std::string backend;
    uint32_t threads = 0;
    bool wants_bvh_nodes = false;
    std::vector<int> codecs;  // wire FrameCodec values, preferred first
    uint64_t session_id = 0;
    std::string address;  // remote endpoint
};

// Error codes sent to misbehaving peers (wire ErrorCode values).
enum class ProtocolError : int {
    bad_version = 1,
    malformed = 2,
    oversized = 3,
    out_of_order = 4,
    unauthenticated = 5,
    wrong_role = 6,
    timeout = 7
};

// on_closed's reason when the peer ended the connection cleanly (FIN, or TLS close_notify),
// as opposed to a lost connection ("connection lost: ...") or a local close.
inline constexpr char kClosedByPeer[] = "closed by the peer";

class Session {
public:
    virtual ~Session() = default;
    // Queues a serialised Envelope. Thread-safe; dropped once the session closed.
    virtual void send(std::string envelope) = 0;
    // Sends an Error envelope, flushes, and closes. Thread-safe, idempotent.
    virtual void reject(ProtocolError code, std::string message) = 0;
    // Sends what is already queued, then closes. Thread-safe, idempotent.
    virtual void close(std::string reason) = 0;
    virtual bool open() const = 0;
    virtual const PeerInfo& peer() const = 0;
    // Bytes handed to send() and not yet written to the socket: a peer that reads slower
    // than it is sent to (or not at all) makes this grow. Thread-safe.
    virtual std::size_t unsent_bytes() const { return 0; }

    // Called on the network thread. Servers set them in on_session; clients pass them in
    // ClientConfig so that nothing the server sends right after the handshake is lost.
    std::function<void(std::string&& envelope)> on_message;
    std::function<void(const std::string& reason)> on_closed;
};

struct ServerConfig {
    uint16_t port = 0;  // 0: an ephemeral port (returned by listen)
    std::string bind_address = "0.0.0.0";
    std::vector<PeerRole> roles;  // roles accepted on this port
    std::string secret;
    uint32_t max_message_bytes = 64u << 20;
    std::chrono::milliseconds handshake_timeout{5000};  // TLS and the handshake, each
    bool tls = true;  // false only for --insecure-plaintext (benchmarks)
};

struct ClientConfig {
    std::string host = "127.0.0.1";
    uint16_t port = 0;
    PeerInfo hello;  // role, name and capabilities to announce
    std::string secret;
    // Installed on the session before its first message is read (the server may send at once).
    std::function<void(std::string&& envelope)> on_message;
    std::function<void(const std::string& reason)> on_closed;
    uint32_t max_message_bytes = 128u << 20;
    std::chrono::milliseconds handshake_timeout{5000};
    bool tls = true;  // false only for --insecure-plaintext (benchmarks)
};

class NetService {
public:
    NetService();
    ~NetService();  // stops the thread; open sessions are closed
    NetService(const NetService&) = delete;
    NetService& operator=(const NetService&) = delete;

    // Listens; on_session is called on the network thread for each authenticated peer.
    Result<uint16_t> listen(const ServerConfig& config,
                            std::function<void(std::shared_ptr<Session>)> on_session);
    // Connects and completes the handshake, then calls done on the network thread.
    void connect(const ClientConfig& config,
                 std::function<void(Result<std::shared_ptr<Session>>)> done);
    // Blocking form of connect for daemons and tests.
    Result<std::shared_ptr<Session>> connect_sync(const ClientConfig& config);
    void post(std::function<void()> task);

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace pathfarm::net
