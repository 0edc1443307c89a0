// Asio C++20-coroutine sessions: handshake, a reader, a writer draining a send queue, and a
// deadline on every read. All socket work runs on the NetService's single network thread.
#include "common/net/session.h"

#include <atomic>
#include <deque>
#include <future>
#include <optional>
#include <thread>

#include <spdlog/spdlog.h>
#include <asio.hpp>

#include "common/net/auth.h"
#include "common/net/framing.h"
#include "common/net/handshake.h"

namespace pathfarm::net {
namespace {

using asio::awaitable;
using asio::use_awaitable;
using asio::ip::tcp;
using Clock = std::chrono::steady_clock;

struct Rejection {  // thrown inside coroutines when a peer broke the protocol
    ProtocolError code;
    std::string message;
};

// A handshake envelope of the expected kind; anything else is a protocol violation.
HandshakeMessage expect(const std::string& bytes, HandshakeMessage::Kind kind, const char* what) {
    HandshakeMessage m = decode_handshake(bytes);
    if (m.kind == HandshakeMessage::Kind::invalid) throw Rejection{m.failure, m.message};
    if (m.kind != kind)
        throw Rejection{ProtocolError::out_of_order, fmt::format("expected {}", what)};
    return m;
}

// On the dialling side the server may refuse with an Error envelope instead.
HandshakeMessage expect_reply(const std::string& bytes) {
    HandshakeMessage m = decode_handshake(bytes);
    if (m.kind == HandshakeMessage::Kind::error) throw std::runtime_error("refused: " + m.message);
    if (m.kind == HandshakeMessage::Kind::invalid) throw Rejection{m.failure, m.message};
    return m;
}

class AsioSession final : public Session, public std::enable_shared_from_this<AsioSession> {
public:
    AsioSession(tcp::socket socket, uint32_t max_bytes, PeerInfo peer)
        : socket_(std::move(socket)),
          wake_(socket_.get_executor()),
          deadline_(socket_.get_executor()),
          max_bytes_(max_bytes),
          peer_(std::move(peer)) {
        wake_.expires_at(Clock::time_point::max());
    }

    void send(std::string envelope) override {
        asio::post(socket_.get_executor(),
                   [self = shared_from_this(), bytes = frame(envelope)]() mutable {
                       if (!self->open_ || self->closing_) return;
                       self->queue_.push_back(std::move(bytes));
                       self->wake_.cancel_one();
                   });
    }
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
        });
    }
    bool open() const override { return open_; }
    const PeerInfo& peer() const override { return peer_; }
    PeerInfo& mutable_peer() { return peer_; }

    // Reads one framed message within `timeout` (Clock::duration::max(): no deadline).
    awaitable<std::string> read_message(Clock::duration timeout) {
        timed_out_ = false;
        if (timeout != Clock::duration::max()) {
            deadline_.expires_after(timeout);
            deadline_.async_wait([weak = weak_from_this()](const asio::error_code& ec) {
                if (auto self = weak.lock(); self && !ec) {
                    self->timed_out_ = true;
                    asio::error_code ignored;
                    self->socket_.cancel(ignored);
                }
            });
        }
        try {
            unsigned char header[kFrameHeaderBytes];
            co_await asio::async_read(socket_, asio::buffer(header), use_awaitable);
            auto size = read_frame_header(header, max_bytes_);
            if (!size) {
                deadline_.cancel();
                throw Rejection{ProtocolError::oversized, size.error().message};
            }
            std::string body(*size, '\0');
            co_await asio::async_read(socket_, asio::buffer(body), use_awaitable);
            deadline_.cancel();
            co_return body;
        } catch (const asio::system_error&) {
            deadline_.cancel();
            if (timed_out_)
                throw Rejection{ProtocolError::timeout, "no message within the deadline"};
            throw;
        }
    }

    awaitable<void> write_now(const std::string& envelope) {
        const std::string bytes = frame(envelope);
        co_await asio::async_write(socket_, asio::buffer(bytes), use_awaitable);
    }

    // After the handshake: deliver messages to on_message until the peer leaves or misbehaves.
    void start() {
        open_ = true;
        asio::co_spawn(socket_.get_executor(), reader(shared_from_this()), asio::detached);
        asio::co_spawn(socket_.get_executor(), writer(shared_from_this()), asio::detached);
    }

    void reject_now(ProtocolError code, const std::string& message) {
        if (!open_ || closing_) return;
        spdlog::warn("{} {}: {}; disconnecting", role_name(peer_.role), peer_.address, message);
        queue_.push_back(frame(error_envelope(code, message)));
        closing_ = true;
        close_reason_ = message;
        wake_.cancel_one();
    }

    void close_now(const std::string& reason) {
        if (closed_) return;
        closed_ = true;
        open_ = false;
        asio::error_code ignored;
        socket_.shutdown(tcp::socket::shutdown_both, ignored);
        socket_.close(ignored);
        wake_.cancel();
        deadline_.cancel();
        if (on_closed) on_closed(reason);
        on_message = nullptr;  // break cycles through captured session pointers
        on_closed = nullptr;
    }

private:
    static awaitable<void> reader(std::shared_ptr<AsioSession> self) {
        try {
            for (;;) {
                std::string message = co_await self->read_message(Clock::duration::max());
                if (!self->open_ || self->closing_) co_return;
                if (self->on_message) self->on_message(std::move(message));
            }
        } catch (const Rejection& r) {
            self->reject_now(r.code, r.message);
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
                co_await asio::async_write(self->socket_, asio::buffer(bytes), use_awaitable);
            }
        } catch (const std::exception& e) {
            self->close_now(std::string("write failed: ") + e.what());
            co_return;
        }
        self->close_now(self->close_reason_.empty() ? "closed" : self->close_reason_);
    }

    tcp::socket socket_;
    asio::steady_timer wake_;      // wakes the writer when the queue fills
    asio::steady_timer deadline_;  // bounds each read
    uint32_t max_bytes_;
    PeerInfo peer_;
    std::deque<std::string> queue_;
    std::atomic<bool> open_{false};
    bool closing_ = false, closed_ = false, timed_out_ = false;
    std::string close_reason_;
};

std::string remote_address(const tcp::socket& s) {
    asio::error_code ec;
    const auto ep = s.remote_endpoint(ec);
    return ec ? std::string("?") : ep.address().to_string() + ":" + std::to_string(ep.port());
}

}  // namespace

const char* role_name(PeerRole role) { return role == PeerRole::tracer ? "tracer" : "client"; }

struct NetService::Impl {
    asio::io_context io;
    asio::executor_work_guard<asio::io_context::executor_type> work{io.get_executor()};
    std::vector<std::shared_ptr<tcp::acceptor>> acceptors;
    std::atomic<uint64_t> next_session{1};
    std::thread thread;

    static awaitable<void> serve(std::shared_ptr<AsioSession> s, ServerConfig config, uint64_t id,
                                 std::function<void(std::shared_ptr<Session>)> on_session) {
        std::optional<Rejection> rejection;
        try {
            using Kind = HandshakeMessage::Kind;
            const HandshakeMessage hello = expect(
                co_await s->read_message(config.handshake_timeout), Kind::hello, "Hello first");
            PeerInfo& peer = s->mutable_peer();
            const std::string address = peer.address;
            peer = hello.peer;
            peer.session_id = id;
            peer.address = address;
            if (hello.nonce.size() != kNonceBytes)
                throw Rejection{ProtocolError::malformed, "bad nonce"};
            if (std::find(config.roles.begin(), config.roles.end(), peer.role) ==
                config.roles.end())
                throw Rejection{
                    ProtocolError::wrong_role,
                    fmt::format("role {} not served on this port", role_name(peer.role))};
            const std::string server_nonce = make_nonce();
            co_await s->write_now(challenge_envelope(server_nonce));
            const HandshakeMessage proof = expect(
                co_await s->read_message(config.handshake_timeout), Kind::proof, "AuthProof");
            if (!macs_equal(proof.mac, client_mac(config.secret, role_name(peer.role), hello.nonce,
                                                  server_nonce)))
                throw Rejection{ProtocolError::unauthenticated, "authentication failed"};
            co_await s->write_now(
                welcome_envelope(id, server_mac(config.secret, hello.nonce, server_nonce)));
            spdlog::info("{} \"{}\" connected from {}", role_name(peer.role), peer.name,
                         peer.address);
            on_session(s);  // handlers are set before the reader delivers anything
            s->start();
        } catch (const Rejection& r) {
            rejection = r;
        } catch (const std::exception& e) {
            s->close_now(std::string("handshake failed: ") + e.what());
            co_return;
        }
        if (!rejection) co_return;
        spdlog::warn("peer {}: {}; disconnecting", s->peer().address, rejection->message);
        try {  // tell the peer why, then close; a peer that vanished does not matter here
            co_await s->write_now(error_envelope(rejection->code, rejection->message));
        } catch (const std::exception&) {
        }
        s->close_now(rejection->message);
    }

    static awaitable<void> accept_loop(Impl* impl, std::shared_ptr<tcp::acceptor> acceptor,
                                       ServerConfig config,
                                       std::function<void(std::shared_ptr<Session>)> on_session) {
        for (;;) {
            asio::error_code ec;
            tcp::socket socket =
                co_await acceptor->async_accept(asio::redirect_error(use_awaitable, ec));
            if (ec) {
                if (ec == asio::error::operation_aborted || !acceptor->is_open()) co_return;
                continue;
            }
            socket.set_option(tcp::no_delay(true), ec);
            PeerInfo peer;
            peer.address = remote_address(socket);
            auto s =
                std::make_shared<AsioSession>(std::move(socket), config.max_message_bytes, peer);
            asio::co_spawn(impl->io, serve(s, config, impl->next_session++, on_session),
                           asio::detached);
        }
    }

    static awaitable<void> dial(Impl* impl, ClientConfig config,
                                std::function<void(Result<std::shared_ptr<Session>>)> done) {
        std::shared_ptr<AsioSession> s;
        try {
            tcp::resolver resolver(impl->io);
            const auto endpoints = co_await resolver.async_resolve(
                config.host, std::to_string(config.port), use_awaitable);
            tcp::socket socket(impl->io);
            co_await asio::async_connect(socket, endpoints, use_awaitable);
            socket.set_option(tcp::no_delay(true));
            PeerInfo server;
            server.address = remote_address(socket);
            server.role = config.hello.role;
            s = std::make_shared<AsioSession>(std::move(socket), config.max_message_bytes, server);
            using Kind = HandshakeMessage::Kind;
            const std::string cn = make_nonce();
            co_await s->write_now(hello_envelope(config.hello, cn));
            const HandshakeMessage challenge =
                expect_reply(co_await s->read_message(config.handshake_timeout));
            if (challenge.kind != Kind::challenge)
                throw std::runtime_error("server did not send a challenge");
            co_await s->write_now(proof_envelope(
                client_mac(config.secret, role_name(config.hello.role), cn, challenge.nonce)));
            const HandshakeMessage welcome =
                expect_reply(co_await s->read_message(config.handshake_timeout));
            if (welcome.kind != Kind::welcome ||
                !macs_equal(welcome.mac, server_mac(config.secret, cn, challenge.nonce)))
                throw std::runtime_error("the server failed to authenticate (wrong secret?)");
            s->mutable_peer().session_id = welcome.session_id;
            s->on_message = config.on_message;
            s->on_closed = config.on_closed;
            s->start();
            done(std::shared_ptr<Session>(s));
        } catch (const Rejection& r) {
            if (s) s->close_now(r.message);
            done(make_error(ErrorCode::io_error, "{}:{}: {}", config.host, config.port, r.message));
        } catch (const std::exception& e) {
            if (s) s->close_now(e.what());
            done(make_error(ErrorCode::io_error, "{}:{}: {}", config.host, config.port, e.what()));
        }
    }
};

NetService::NetService() : impl_(std::make_unique<Impl>()) {
    impl_->thread = std::thread([impl = impl_.get()] { impl->io.run(); });
}

NetService::~NetService() {
    asio::post(impl_->io, [impl = impl_.get()] {
        for (auto& a : impl->acceptors) {
            asio::error_code ignored;
            a->close(ignored);
        }
    });
    impl_->work.reset();
    impl_->io.stop();
    if (impl_->thread.joinable()) impl_->thread.join();
}

Result<uint16_t> NetService::listen(const ServerConfig& config,
                                    std::function<void(std::shared_ptr<Session>)> on_session) {
    try {
        auto acceptor = std::make_shared<tcp::acceptor>(impl_->io);
        const tcp::endpoint ep(asio::ip::make_address(config.bind_address), config.port);
        acceptor->open(ep.protocol());
        acceptor->set_option(tcp::acceptor::reuse_address(true));
        acceptor->bind(ep);
        acceptor->listen();
        const uint16_t port = acceptor->local_endpoint().port();
        asio::post(impl_->io,
                   [impl = impl_.get(), acceptor] { impl->acceptors.push_back(acceptor); });
        asio::co_spawn(impl_->io,
                       Impl::accept_loop(impl_.get(), acceptor, config, std::move(on_session)),
                       asio::detached);
        return port;
    } catch (const std::exception& e) {
        return make_error(ErrorCode::io_error, "listen on {}:{}: {}", config.bind_address,
                          config.port, e.what());
    }
}

void NetService::connect(const ClientConfig& config,
                         std::function<void(Result<std::shared_ptr<Session>>)> done) {
    asio::co_spawn(impl_->io, Impl::dial(impl_.get(), config, std::move(done)), asio::detached);
}

Result<std::shared_ptr<Session>> NetService::connect_sync(const ClientConfig& config) {
    auto promise = std::make_shared<std::promise<Result<std::shared_ptr<Session>>>>();
    auto future = promise->get_future();
    connect(config,
            [promise](Result<std::shared_ptr<Session>> r) { promise->set_value(std::move(r)); });
    return future.get();
}

void NetService::post(std::function<void()> task) { asio::post(impl_->io, std::move(task)); }

}  // namespace pathfarm::net
