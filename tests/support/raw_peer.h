// A raw TCP peer for tests that send what a well-behaved client never would: blocking
// sockets, optionally inside a TLS 1.3 tunnel keyed by the farm secret (as a real peer's), so
// the same abuse reaches the handshake in both modes.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

struct ssl_st;
struct ssl_ctx_st;

namespace pathfarm::test {

class RawPeer {
public:
    // tls_secret: empty for plaintext; else the TLS handshake runs in the constructor.
    explicit RawPeer(uint16_t port, const std::string& tls_secret = "");
    ~RawPeer();
    RawPeer(const RawPeer&) = delete;
    RawPeer& operator=(const RawPeer&) = delete;

    bool connected() const { return connected_; }
    // TLS: the key exchange group's OpenSSL NID (0: none, a PSK-only handshake).
    int key_exchange_group() const;
    void send_bytes(const std::string& bytes);
    // Reads one framed message body; nullopt on close or timeout (3 s).
    std::optional<std::string> receive_frame();
    // True when the peer ended the stream: TLS: its close_notify, which we answer (or, with
    // answer = false, do not: the TCP close must still follow, the peer's shutdown being
    // bounded by its own timer), then the TCP close.
    bool closed_by_peer(bool answer = true);

private:
    bool read_all(void* p, std::size_t n);
    int fd_ = -1;
    bool connected_ = false;
    ssl_ctx_st* ctx_ = nullptr;
    ssl_st* ssl_ = nullptr;
    std::string psk_;
};

}  // namespace pathfarm::test
