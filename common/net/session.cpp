// Asio C++20-coroutine sessions: TLS, handshake, a reader, a writer draining a send queue, and
// a deadline on every read. All socket work runs on the NetService's single network thread.
#include "common/net/session.h"

#include <future>
#include <thread>

#include "common/net/asio_session.h"
#include "common/net/auth.h"

namespace pathfarm::net {
namespace {

using asio::awaitable;
using asio::use_awaitable;
using asio::ip::tcp;
using detail::AsioSession;
using detail::expect;
using detail::expect_reply;
using detail::make_tls_context;
using detail::Rejection;
using detail::TlsContext;

void warn_plaintext(const std::string& link) {
    spdlog::warn(
        "INSECURE: {} without TLS (--insecure-plaintext): anyone on the path reads the "
        "game and can inject rows; for benchmarks only",
        link);
}

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

    // The server's TLS handshake; false (logged, closed) for a peer that does not speak it.
    static awaitable<bool> accept_tls(std::shared_ptr<AsioSession> s, const ServerConfig& config) {
        std::string failure;
        try {
            co_await s->tls_handshake(true, config.handshake_timeout);
        } catch (const std::exception& e) {
            failure = e.what();
        }
        if (failure.empty()) co_return true;
        // Nothing to tell a peer that does not speak our TLS.
        spdlog::warn(
            "peer {}: {}: not a TLS peer of this farm (plaintext, or another farm secret); "
            "disconnecting",
            s->peer().address, failure);
        s->close_now(failure);
        co_return false;
    }

    static awaitable<void> serve(std::shared_ptr<AsioSession> s, ServerConfig config, uint64_t id,
                                 std::function<void(std::shared_ptr<Session>)> on_session) {
        if (s->uses_tls() && !co_await accept_tls(s, config)) co_return;
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
                                       ServerConfig config, std::shared_ptr<TlsContext> tls,
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
            auto s = std::make_shared<AsioSession>(std::move(socket), config.max_message_bytes,
                                                   peer, tls);
            asio::co_spawn(impl->io, serve(s, config, impl->next_session++, on_session),
                           asio::detached);
        }
    }

    static awaitable<void> dial(Impl* impl, ClientConfig config,
                                std::function<void(Result<std::shared_ptr<Session>>)> done) {
        std::shared_ptr<AsioSession> s;
        try {
            std::shared_ptr<TlsContext> tls;
            if (!config.tls) warn_plaintext(fmt::format("{}:{}", config.host, config.port));
            if (config.tls) {
                auto context = make_tls_context(false, config.secret);
                if (!context) throw std::runtime_error(context.error().message);
                tls = *context;
            }
            tcp::resolver resolver(impl->io);
            const auto endpoints = co_await resolver.async_resolve(
                config.host, std::to_string(config.port), use_awaitable);
            tcp::socket socket(impl->io);
            co_await asio::async_connect(socket, endpoints, use_awaitable);
            socket.set_option(tcp::no_delay(true));
            PeerInfo server;
            server.address = remote_address(socket);
            server.role = config.hello.role;
            s = std::make_shared<AsioSession>(std::move(socket), config.max_message_bytes, server,
                                              tls);
            if (tls) {
                try {
                    co_await s->tls_handshake(false, config.handshake_timeout);
                } catch (const std::exception& e) {
                    throw std::runtime_error(
                        std::string(e.what()) +
                        ": does the other end run with --insecure-plaintext or another secret?");
                }
            }
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
        std::shared_ptr<TlsContext> tls;
        if (!config.tls) warn_plaintext(fmt::format("port {}", config.port));
        if (config.tls) {
            auto context = make_tls_context(true, config.secret);
            if (!context)
                return make_error(ErrorCode::io_error, "listen on {}:{}: {}", config.bind_address,
                                  config.port, context.error().message);
            tls = *context;
        }
        auto acceptor = std::make_shared<tcp::acceptor>(impl_->io);
        const tcp::endpoint ep(asio::ip::make_address(config.bind_address), config.port);
        acceptor->open(ep.protocol());
        acceptor->set_option(tcp::acceptor::reuse_address(true));
        acceptor->bind(ep);
        acceptor->listen();
        const uint16_t port = acceptor->local_endpoint().port();
        asio::post(impl_->io,
                   [impl = impl_.get(), acceptor] { impl->acceptors.push_back(acceptor); });
        asio::co_spawn(
            impl_->io,
            Impl::accept_loop(impl_.get(), acceptor, config, std::move(tls), std::move(on_session)),
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
