// The session behind NetService (session.cpp): one TCP connection, optionally inside TLS
// (tls_psk.h), with a reader, a writer draining a send queue and a deadline on every read.
// Internal to common/net: Asio and OpenSSL live here, never in widely included headers.
#pragma once

#include <atomic>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>
#include <asio.hpp>
#include <asio/ssl.hpp>

#include "common/net/framing.h"
#include "common/net/handshake.h"
#include "common/net/session.h"
#include "common/net/tls_psk.h"

namespace pathfarm::net::detail {
using asio::awaitable;
using asio::use_awaitable;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

// How long a closing TLS session waits for the peer's close_notify, which may never come.
constexpr auto kTlsShutdownTimeout = std::chrono::milliseconds(1000);
// How long a closing session may take to send what is queued.
constexpr auto kCloseTimeout = std::chrono::milliseconds(2000);

// An OpenSSL context keyed by the farm secret, shared by the sessions of one listen or dial.
struct TlsContext {
    asio::ssl::context ssl;
    std::string psk;
    explicit TlsContext(bool server)
        : ssl(server ? asio::ssl::context::tls_server : asio::ssl::context::tls_client) {}
};

inline Result<std::shared_ptr<TlsContext>> make_tls_context(bool server,
                                                            const std::string& secret) {
    auto context = std::make_shared<TlsContext>(server);
    context->psk = tls_psk(secret);
    if (Status s = use_farm_psk(context->ssl.native_handle(), server, &context->psk); !s)
        return s.error();
    return context;
}

struct Rejection {  // thrown inside coroutines when a peer broke the protocol
    ProtocolError code;
    std::string message;
};

// A handshake envelope of the expected kind; anything else is a protocol violation.
inline HandshakeMessage expect(const std::string& bytes, HandshakeMessage::Kind kind,
                               const char* what) {
    HandshakeMessage m = decode_handshake(bytes);
    if (m.kind == HandshakeMessage::Kind::invalid) throw Rejection{m.failure, m.message};
    if (m.kind != kind)
        throw Rejection{ProtocolError::out_of_order, fmt::format("expected {}", what)};
    return m;
}

// On the dialling side the server may refuse with an Error envelope instead.
inline HandshakeMessage expect_reply(const std::string& bytes) {
    HandshakeMessage m = decode_handshake(bytes);
    if (m.kind == HandshakeMessage::Kind::error) throw std::runtime_error("refused: " + m.message);
    if (m.kind == HandshakeMessage::Kind::invalid) throw Rejection{m.failure, m.message};
    return m;
}

class AsioSession final : public Session, public std::enable_shared_from_this<AsioSession> {
public:
    // tls: the context to encrypt with, or null for --insecure-plaintext.
    AsioSession(tcp::socket socket, uint32_t max_bytes, PeerInfo peer,
                std::shared_ptr<TlsContext> tls)
        : socket_(std::move(socket)),
          tls_context_(std::move(tls)),
          wake_(socket_.get_executor()),
          deadline_(socket_.get_executor()),
          close_timer_(socket_.get_executor()),
          max_bytes_(max_bytes),
          peer_(std::move(peer)) {
        wake_.expires_at(Clock::time_point::max());
        if (tls_context_) tls_.emplace(socket_, tls_context_->ssl);
    }

    void send(std::string envelope) override {
        unsent_ += envelope.size() + kFrameHeaderBytes;
        asio::post(socket_.get_executor(),
                   [self = shared_from_this(), bytes = frame(envelope)]() mutable {
                       if (!self->open_ || self->closing_) {
                           self->unsent_ -= bytes.size();
                           return;
                       }
                       self->queue_.push_back(std::move(bytes));
                       self->wake_.cancel_one();
                   });
    }
    std::size_t unsent_bytes() const override { return unsent_; }
    void reject(ProtocolError code, std::string message) override {
        asio::post(socket_.get_executor(),
                   [self = shared_from_this(), code, message = std::move(message)] {
                       self->reject_now(code, message);
                   });
    }
    void close(std::string reason) override {
        asio::post(socket_.get_executor(), [self = shared_from_this(), reason = std::move(reason)] {
            if (!self->open_) return self->close_now(reason);
            if (self->closing_) return;
            self->closing_ = true;  // the writer sends what is queued, then closes
            self->close_reason_ = reason;
            self->wake_.cancel_one();
            self->bound_close();
        });
    }
    bool open() const override { return open_; }
    bool uses_tls() const { return tls_.has_value(); }
    const PeerInfo& peer() const override { return peer_; }
    PeerInfo& mutable_peer() { return peer_; }

    // The TLS handshake within `timeout`; throws std::runtime_error with a one-line reason.
    awaitable<void> tls_handshake(bool server, Clock::duration timeout) {
        arm_deadline(timeout);
        try {
            co_await tls_->async_handshake(
                server ? asio::ssl::stream_base::server : asio::ssl::stream_base::client,
                use_awaitable);
            deadline_.cancel();
        } catch (const asio::system_error& e) {
            deadline_.cancel();
            throw std::runtime_error(timed_out_
                                         ? std::string("no TLS handshake within the deadline")
                                         : "TLS handshake failed (" + e.code().message() + ")");
        }
        tls_ready_ = true;
    }

    // Reads one framed message within `timeout` (Clock::duration::max(): no deadline).
    awaitable<std::string> read_message(Clock::duration timeout) {
        arm_deadline(timeout);
        try {
            unsigned char header[kFrameHeaderBytes];
            co_await read_exactly(asio::buffer(header));
            if (!tls_ && header[0] == 0x16 && header[1] == 0x03) {  // a TLS record header
                deadline_.cancel();
                throw Rejection{ProtocolError::malformed,
                                "a TLS peer on a plaintext link (this end runs "
                                "--insecure-plaintext, the peer does not)"};
            }
            auto size = read_frame_header(header, max_bytes_);
            if (!size) {
                deadline_.cancel();
                throw Rejection{ProtocolError::oversized, size.error().message};
            }
            std::string body(*size, '\0');
            co_await read_exactly(asio::buffer(body));
            deadline_.cancel();
            co_return body;
        } catch (const asio::system_error&) {
            deadline_.cancel();
            if (timed_out_)
                throw Rejection{ProtocolError::timeout, "no message within the deadline"};
            throw;
        }
    }

    awaitable<void> write_now(const std::string& envelope) { co_await write_all(frame(envelope)); }

    // After the handshake: deliver messages to on_message until the peer leaves or misbehaves.
    void start() {
        open_ = true;
        asio::co_spawn(socket_.get_executor(), reader(shared_from_this()), asio::detached);
        asio::co_spawn(socket_.get_executor(), writer(shared_from_this()), asio::detached);
    }

    // A peer that reads nothing (a half-open connection) can keep the writer from ever
    // draining the queue: closing takes at most kCloseTimeout either way.
    void bound_close() {
        close_timer_.expires_after(kCloseTimeout);
        close_timer_.async_wait([self = shared_from_this()](const asio::error_code& ec) {
            if (!ec) self->close_now(self->close_reason_ + " (the peer stopped reading)");
        });
    }

    void reject_now(ProtocolError code, const std::string& message) {
        if (!open_ || closing_) return;
        spdlog::warn("{} {}: {}; disconnecting", role_name(peer_.role), peer_.address, message);
        queue_.push_back(frame(error_envelope(code, message)));
        unsent_ += queue_.back().size();
        closing_ = true;
        close_reason_ = message;
        wake_.cancel_one();
        bound_close();
    }

    void close_now(const std::string& reason) {
        if (closed_) return;
        closed_ = true;
        open_ = false;
        wake_.cancel();
        deadline_.cancel();
        close_timer_.cancel();
        if (tls_ready_)
            shutdown_tls();
        else
            close_socket();
        if (on_closed) on_closed(reason);
        on_message = nullptr;  // break cycles through captured session pointers
        on_closed = nullptr;
    }

private:
    void arm_deadline(Clock::duration timeout) {
        timed_out_ = false;
        if (timeout == Clock::duration::max()) return;
        deadline_.expires_after(timeout);
        deadline_.async_wait([weak = weak_from_this()](const asio::error_code& ec) {
            if (auto self = weak.lock(); self && !ec) {
                self->timed_out_ = true;
                asio::error_code ignored;
                self->socket_.cancel(ignored);
            }
        });
    }

    awaitable<void> read_exactly(asio::mutable_buffer buffer) {
        if (tls_)
            co_await asio::async_read(*tls_, buffer, use_awaitable);
        else
            co_await asio::async_read(socket_, buffer, use_awaitable);
    }

    awaitable<void> write_all(const std::string& bytes) {
        if (tls_)
            co_await asio::async_write(*tls_, asio::buffer(bytes), use_awaitable);
        else
            co_await asio::async_write(socket_, asio::buffer(bytes), use_awaitable);
    }

    void close_socket() {
        asio::error_code ignored;
        socket_.shutdown(tcp::socket::shutdown_both, ignored);
        socket_.close(ignored);
    }

    // Sends close_notify and waits for the peer's, bounded by a timer: a peer that vanished
    // or never answers does not keep the socket open.
    // The timer is close_timer_, free once closed: the cancelled reader's handler runs after
    // this and cancels deadline_, which left a peer that never answered holding the socket
    // (the 30-minute soak's slow climb of file descriptors and memory).
    void shutdown_tls() {
        asio::error_code ignored;
        socket_.cancel(ignored);  // a pending read ends; the shutdown reads for itself
        close_timer_.expires_after(kTlsShutdownTimeout);
        close_timer_.async_wait([self = shared_from_this()](const asio::error_code& ec) {
            if (!ec) self->close_socket();
        });
        tls_->async_shutdown([self = shared_from_this()](const asio::error_code&) {
            self->close_timer_.cancel();
            self->close_socket();
        });
    }

    static awaitable<void> reader(std::shared_ptr<AsioSession> self) {
        try {
            for (;;) {
                std::string message = co_await self->read_message(Clock::duration::max());
                if (!self->open_ || self->closing_) co_return;
                if (self->on_message) self->on_message(std::move(message));
            }
        } catch (const Rejection& r) {
            self->reject_now(r.code, r.message);
        } catch (const asio::system_error& e) {
            // A clean end (FIN, or TLS close_notify) is the peer closing; anything else (a
            // reset, a TLS stream cut short) is a lost connection, which clients retry.
            self->close_now(self->closing_ ? self->close_reason_
                            : e.code() == asio::error::eof
                                ? std::string(kClosedByPeer)
                                : "connection lost: " + e.code().message());
        } catch (const std::exception& e) {
            self->close_now(self->closing_ ? self->close_reason_
                                           : std::string("connection lost: ") + e.what());
        }
    }

    static awaitable<void> writer(std::shared_ptr<AsioSession> self) {
        try {
            while (!self->closed_) {
                if (self->queue_.empty()) {
                    if (self->closing_) break;
                    asio::error_code ec;
                    co_await self->wake_.async_wait(asio::redirect_error(use_awaitable, ec));
                    continue;
                }
                const std::string bytes = std::move(self->queue_.front());
                self->queue_.pop_front();
                co_await self->write_all(bytes);
                self->unsent_ -= bytes.size();
            }
        } catch (const std::exception& e) {
            self->close_now(std::string("write failed: ") + e.what());
            co_return;
        }
        self->close_now(self->close_reason_.empty() ? "closed" : self->close_reason_);
    }

    tcp::socket socket_;
    std::shared_ptr<TlsContext> tls_context_;             // declared before tls_: outlives it
    std::optional<asio::ssl::stream<tcp::socket&>> tls_;  // over socket_, unless plaintext
    asio::steady_timer wake_;                             // wakes the writer when the queue fills
    asio::steady_timer deadline_;                         // bounds each read
    asio::steady_timer close_timer_;                      // bounds a close
    uint32_t max_bytes_;
    PeerInfo peer_;
    std::deque<std::string> queue_;
    std::atomic<bool> open_{false};
    std::atomic<std::size_t> unsent_{0};  // sent and not yet written (queued or in flight)
    bool closing_ = false, closed_ = false, timed_out_ = false, tls_ready_ = false;
    std::string close_reason_;
};

}  // namespace pathfarm::net::detail
