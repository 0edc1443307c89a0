// websocketpp on a standalone-Asio loop of its own: a stalled browser or a flood of requests
// cannot delay the tracers' sessions (common/net), which run on the farm's loop. C++17 (see
// the header); everything that touches the server or its connections runs on its thread.
#include "coordinator/http/web_server.h"

#include <chrono>
#include <future>
#include <map>
#include <thread>

#include <spdlog/spdlog.h>
#include <websocketpp/config/asio.hpp>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace pathfarm::coord {
namespace {

using Handle = websocketpp::connection_hdl;

template <typename Connection>
HttpRequest request_of(const Connection& con) {
    return {con->get_request().get_method(), con->get_resource(),
            con->get_request_header("Cookie")};
}

template <typename Connection>
void respond(const Connection& con, const HttpResponse& r) {
    con->set_status(websocketpp::http::status_code::value(r.status));
    con->replace_header("Content-Type", r.content_type);
    con->replace_header("Cache-Control", "no-store");
    for (const auto& [name, value] : r.headers)
        con->append_header(name, value);
    con->set_body(r.body);
}

}  // namespace

// The server behind WebServer: plain (websocketpp::config::asio) or TLS (asio_tls).
struct WebServer::Impl {
    virtual ~Impl() = default;
    virtual std::optional<uint16_t> start(const std::string& bind_address, uint16_t port,
                                          std::string& error) = 0;
    virtual void send(uint64_t client, std::shared_ptr<const std::string> message,
                      std::size_t max_buffered, MessageKind kind) = 0;
    virtual void close(uint64_t client, const std::string& reason) = 0;
    virtual void stop() = 0;
};

namespace {

template <typename Config>
struct ServerImpl final : WebServer::Impl {
    using Server = websocketpp::server<Config>;
    static constexpr bool kTls = !std::is_same_v<Config, websocketpp::config::asio>;

    ServerImpl(WebServerHandlers h, std::optional<TlsFiles> tls_files)
        : handlers(std::move(h)), tls(std::move(tls_files)) {
        install();
    }
    ~ServerImpl() override { stop(); }

    std::optional<uint16_t> start(const std::string& bind_address, uint16_t port,
                                  std::string& error) override;
    void send(uint64_t client, std::shared_ptr<const std::string> message, std::size_t max_buffered,
              MessageKind kind) override;
    void close(uint64_t client, const std::string& reason) override;
    void stop() override;

    void install();
    void on_http(Handle h);
    bool on_validate(Handle h);
    void on_open(Handle h);
    void on_close(Handle h);
    void on_message(Handle h, typename Server::message_ptr m);

    WebServerHandlers handlers;
    std::optional<TlsFiles> tls;
    std::shared_ptr<asio::ssl::context> tls_context;  // loaded in start()
    asio::io_context io;
    Server server;  // after io: destroyed first (its acceptor belongs to io)
    std::map<Handle, uint64_t, std::owner_less<Handle>> ids;  // open WebSockets
    std::map<uint64_t, Handle> handles;
    std::map<uint64_t, bool> broken;  // a message dropped, no key message since
    uint64_t next_id = 1;
    std::thread thread;
    std::future<void> finished;
};

template <typename Config>
void ServerImpl<Config>::install() {
    server.clear_access_channels(websocketpp::log::alevel::all);
    server.clear_error_channels(websocketpp::log::elevel::all);
    server.init_asio(&io);
    server.set_reuse_addr(true);
    server.set_max_message_size(4096);  // inputs are a few dozen bytes
    server.set_max_http_body_size(4096);
    server.set_open_handshake_timeout(5000);
    server.set_close_handshake_timeout(500);
    server.set_http_handler([this](Handle h) { on_http(h); });
    server.set_validate_handler([this](Handle h) { return on_validate(h); });
    server.set_open_handler([this](Handle h) { on_open(h); });
    server.set_close_handler([this](Handle h) { on_close(h); });
    server.set_fail_handler([this](Handle h) {
        auto con = server.get_con_from_hdl(h);
        spdlog::debug("http: connection from {} failed: {}", con->get_remote_endpoint(),
                      con->get_ec().message());
    });
    server.set_message_handler(
        [this](Handle h, typename Server::message_ptr m) { on_message(h, m); });
    if constexpr (kTls) server.set_tls_init_handler([this](Handle) { return tls_context; });
}

template <typename Config>
void ServerImpl<Config>::on_http(Handle h) {
    auto con = server.get_con_from_hdl(h);
    respond(con, handlers.on_http(request_of(con)));
}

template <typename Config>
bool ServerImpl<Config>::on_validate(Handle h) {
    auto con = server.get_con_from_hdl(h);
    const std::optional<HttpResponse> refusal = handlers.on_upgrade(request_of(con));
    if (!refusal) return true;
    respond(con, *refusal);
    return false;
}

template <typename Config>
void ServerImpl<Config>::on_open(Handle h) {
    const uint64_t id = next_id++;
    ids[h] = id;
    handles[id] = h;
    handlers.on_open(id, request_of(server.get_con_from_hdl(h)));
}

template <typename Config>
void ServerImpl<Config>::on_close(Handle h) {
    const auto it = ids.find(h);
    if (it == ids.end()) return;
    const uint64_t id = it->second;
    handles.erase(id);
    broken.erase(id);
    ids.erase(it);
    handlers.on_close(id);
}

template <typename Config>
void ServerImpl<Config>::on_message(Handle h, typename Server::message_ptr m) {
    const auto it = ids.find(h);
    if (it == ids.end()) return;
    if (m->get_opcode() != websocketpp::frame::opcode::binary) {
        websocketpp::lib::error_code ec;
        server.close(h, websocketpp::close::status::unsupported_data, "binary messages only", ec);
        return;
    }
    handlers.on_message(it->second, m->get_payload());
}

template <typename Config>
std::optional<uint16_t> ServerImpl<Config>::start(const std::string& bind_address, uint16_t port,
                                                  std::string& error) {
    ServerImpl& s = *this;
    if constexpr (kTls) {  // TLS 1.2 and 1.3 (browsers), the operator's certificate and key
        tls_context = std::make_shared<asio::ssl::context>(asio::ssl::context::tls_server);
        asio::error_code ec;
        tls_context->set_options(asio::ssl::context::default_workarounds |
                                     asio::ssl::context::no_sslv2 | asio::ssl::context::no_sslv3 |
                                     asio::ssl::context::no_tlsv1 | asio::ssl::context::no_tlsv1_1,
                                 ec);
        if (!ec) tls_context->use_certificate_chain_file(tls->certificate, ec);
        if (ec) {
            error = "--https-cert " + tls->certificate + ": " + ec.message();
            return std::nullopt;
        }
        tls_context->use_private_key_file(tls->key, asio::ssl::context::pem, ec);
        if (ec) {
            error = "--https-key " + tls->key + ": " + ec.message();
            return std::nullopt;
        }
    }
    asio::error_code aec;
    const asio::ip::address address = asio::ip::make_address(bind_address, aec);
    if (aec) {
        error = "--bind " + bind_address + ": " + aec.message();
        return std::nullopt;
    }
    websocketpp::lib::error_code ec;
    s.server.listen(asio::ip::tcp::endpoint(address, port), ec);
    if (!ec) s.server.start_accept(ec);
    if (ec) {
        error = "--http-port " + std::to_string(port) + ": " + ec.message();
        return std::nullopt;
    }
    const uint16_t bound = s.server.get_local_endpoint(aec).port();
    std::promise<void> done;
    s.finished = done.get_future();
    s.thread = std::thread([&s, done = std::move(done)]() mutable {
        s.io.run();
        done.set_value();
    });
    return bound;
}

template <typename Config>
void ServerImpl<Config>::send(uint64_t client, std::shared_ptr<const std::string> message,
                              std::size_t max_buffered, MessageKind kind) {
    ServerImpl& s = *this;
    asio::post(s.io, [&s, client, message = std::move(message), max_buffered, kind] {
        const auto it = s.handles.find(client);
        if (it == s.handles.end()) return;
        websocketpp::lib::error_code ec;
        auto con = s.server.get_con_from_hdl(it->second, ec);
        if (ec) return;
        bool& gap = s.broken[client];
        if (con->get_buffered_amount() > max_buffered || (gap && kind == MessageKind::delta)) {
            if (kind != MessageKind::independent && !gap) {
                gap = true;
                s.handlers.on_dropped(client);
            }
            return;
        }
        if (kind == MessageKind::key) gap = false;
        con->send(message->data(), message->size(), websocketpp::frame::opcode::binary);
    });
}

template <typename Config>
void ServerImpl<Config>::close(uint64_t client, const std::string& reason) {
    ServerImpl& s = *this;
    asio::post(s.io, [&s, client, reason] {
        const auto it = s.handles.find(client);
        if (it == s.handles.end()) return;
        websocketpp::lib::error_code ec;
        s.server.close(it->second, websocketpp::close::status::policy_violation, reason, ec);
    });
}

template <typename Config>
void ServerImpl<Config>::stop() {
    ServerImpl& s = *this;
    if (!s.thread.joinable()) return;
    asio::post(s.io, [&s] {
        websocketpp::lib::error_code ec;
        s.server.stop_listening(ec);
        for (const auto& [id, h] : s.handles)
            s.server.close(h, websocketpp::close::status::going_away, "coordinator finished", ec);
    });
    // The loop ends by itself once every connection has closed; a peer that never answers
    // the close is cut off after the bound.
    if (s.finished.wait_for(std::chrono::seconds(1)) != std::future_status::ready) s.io.stop();
    s.thread.join();
}

}  // namespace

WebServer::WebServer(WebServerHandlers handlers, std::optional<TlsFiles> tls) {
    if (tls)
        impl_ = std::make_unique<ServerImpl<websocketpp::config::asio_tls>>(std::move(handlers),
                                                                            std::move(tls));
    else
        impl_ = std::make_unique<ServerImpl<websocketpp::config::asio>>(std::move(handlers),
                                                                        std::nullopt);
}

WebServer::~WebServer() { stop(); }

std::optional<uint16_t> WebServer::start(const std::string& bind_address, uint16_t port,
                                         std::string& error) {
    return impl_->start(bind_address, port, error);
}

void WebServer::send(uint64_t client, std::shared_ptr<const std::string> message,
                     std::size_t max_buffered, MessageKind kind) {
    impl_->send(client, std::move(message), max_buffered, kind);
}

void WebServer::close(uint64_t client, const std::string& reason) { impl_->close(client, reason); }

void WebServer::stop() { impl_->stop(); }

}  // namespace pathfarm::coord
