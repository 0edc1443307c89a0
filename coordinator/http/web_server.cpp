// websocketpp on a standalone-Asio loop of its own: a stalled browser or a flood of requests
// cannot delay the tracers' sessions (common/net), which run on the farm's loop. C++17 (see
// the header); everything that touches the server or its connections runs on its thread.
#include "coordinator/http/web_server.h"

#include <chrono>
#include <future>
#include <map>
#include <thread>

#include <spdlog/spdlog.h>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace pathfarm::coord {
namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Handle = websocketpp::connection_hdl;

HttpRequest request_of(Server::connection_ptr con) {
    return {con->get_request().get_method(), con->get_resource(),
            con->get_request_header("Cookie")};
}

void respond(Server::connection_ptr con, const HttpResponse& r) {
    con->set_status(websocketpp::http::status_code::value(r.status));
    con->replace_header("Content-Type", r.content_type);
    con->replace_header("Cache-Control", "no-store");
    for (const auto& [name, value] : r.headers)
        con->append_header(name, value);
    con->set_body(r.body);
}

}  // namespace

struct WebServer::Impl {
    explicit Impl(WebServerHandlers h) : handlers(std::move(h)) {}

    void install();
    void on_http(Handle h);
    bool on_validate(Handle h);
    void on_open(Handle h);
    void on_close(Handle h);
    void on_message(Handle h, Server::message_ptr m);

    WebServerHandlers handlers;
    asio::io_context io;
    Server server;  // after io: destroyed first (its acceptor belongs to io)
    std::map<Handle, uint64_t, std::owner_less<Handle>> ids;  // open WebSockets
    std::map<uint64_t, Handle> handles;
    std::map<uint64_t, bool> broken;  // a message dropped, no key message since
    uint64_t next_id = 1;
    std::thread thread;
    std::future<void> finished;
};

void WebServer::Impl::install() {
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
    server.set_message_handler([this](Handle h, Server::message_ptr m) { on_message(h, m); });
}

void WebServer::Impl::on_http(Handle h) {
    auto con = server.get_con_from_hdl(h);
    respond(con, handlers.on_http(request_of(con)));
}

bool WebServer::Impl::on_validate(Handle h) {
    auto con = server.get_con_from_hdl(h);
    const std::optional<HttpResponse> refusal = handlers.on_upgrade(request_of(con));
    if (!refusal) return true;
    respond(con, *refusal);
    return false;
}

void WebServer::Impl::on_open(Handle h) {
    const uint64_t id = next_id++;
    ids[h] = id;
    handles[id] = h;
    handlers.on_open(id, request_of(server.get_con_from_hdl(h)));
}

void WebServer::Impl::on_close(Handle h) {
    const auto it = ids.find(h);
    if (it == ids.end()) return;
    const uint64_t id = it->second;
    handles.erase(id);
    broken.erase(id);
    ids.erase(it);
    handlers.on_close(id);
}

void WebServer::Impl::on_message(Handle h, Server::message_ptr m) {
    const auto it = ids.find(h);
    if (it == ids.end()) return;
    if (m->get_opcode() != websocketpp::frame::opcode::binary) {
        websocketpp::lib::error_code ec;
        server.close(h, websocketpp::close::status::unsupported_data, "binary messages only", ec);
        return;
    }
    handlers.on_message(it->second, m->get_payload());
}

WebServer::WebServer(WebServerHandlers handlers)
    : impl_(std::make_unique<Impl>(std::move(handlers))) {
    impl_->install();
}

WebServer::~WebServer() { stop(); }

std::optional<uint16_t> WebServer::start(const std::string& bind_address, uint16_t port,
                                         std::string& error) {
    Impl& s = *impl_;
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

void WebServer::send(uint64_t client, std::shared_ptr<const std::string> message,
                     std::size_t max_buffered, MessageKind kind) {
    Impl& s = *impl_;
    asio::post(s.io, [&s, client, message = std::move(message), max_buffered, kind] {
        const auto it = s.handles.find(client);
        if (it == s.handles.end()) return;
        websocketpp::lib::error_code ec;
        auto con = s.server.get_con_from_hdl(it->second, ec);
        if (ec) return;
        bool& broken = s.broken[client];
        if (con->get_buffered_amount() > max_buffered || (broken && kind == MessageKind::delta)) {
            if (kind != MessageKind::independent && !broken) {
                broken = true;
                s.handlers.on_dropped(client);
            }
            return;
        }
        if (kind == MessageKind::key) broken = false;
        con->send(message->data(), message->size(), websocketpp::frame::opcode::binary);
    });
}

void WebServer::close(uint64_t client, const std::string& reason) {
    Impl& s = *impl_;
    asio::post(s.io, [&s, client, reason] {
        const auto it = s.handles.find(client);
        if (it == s.handles.end()) return;
        websocketpp::lib::error_code ec;
        s.server.close(it->second, websocketpp::close::status::policy_violation, reason, ec);
    });
}

void WebServer::stop() {
    Impl& s = *impl_;
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

}  // namespace pathfarm::coord
