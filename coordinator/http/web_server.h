// The coordinator's HTTP port (docs/web.md): plain HTTP requests and WebSocket connections on
// an Asio event loop of their own, through websocketpp. Routing and access control are the
// caller's (http_routes.h); this class only moves bytes.
//
// This header and web_server.cpp are C++17: websocketpp 0.8.2 (Debian 12) does not compile as
// C++20, so web_server.cpp is the one C++17 translation unit, and nothing here may need more.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pathfarm::coord {

struct HttpRequest {
    std::string method;    // "GET", ...
    std::string resource;  // path and query, as sent: "/metrics?token=ab"
    std::string cookie;    // the Cookie header, or empty
};

struct HttpResponse {
    int status = 404;
    std::string content_type = "text/plain; charset=utf-8";
    std::string body;
    std::vector<std::pair<std::string, std::string>> headers;  // extra ones (Set-Cookie, ...)
};

struct WebServerHandlers {
    // A plain HTTP request (not an upgrade). Runs on the server's thread.
    std::function<HttpResponse(const HttpRequest&)> on_http;
    // A WebSocket upgrade: nullopt accepts it, a response refuses it with that status.
    std::function<std::optional<HttpResponse>(const HttpRequest&)> on_upgrade;
    std::function<void(uint64_t client, const HttpRequest& upgrade)> on_open;
    std::function<void(uint64_t client, const std::string& binary_message)> on_message;
    std::function<void(uint64_t client)> on_close;
    // A message to `client` was dropped (too much unsent): a stream of deltas needs a new key.
    std::function<void(uint64_t client)> on_dropped;
};

// How a message relates to the ones before it: a delta (an H.264 P-frame) is useless after a
// dropped message until the next key message.
enum class MessageKind { independent, key, delta };

// HTTPS: a PEM certificate chain and its private key (files the operator provides).
struct TlsFiles {
    std::string certificate, key;
};

class WebServer {
public:
    // tls: serve HTTPS and WSS instead of HTTP and WS.
    explicit WebServer(WebServerHandlers handlers, std::optional<TlsFiles> tls = std::nullopt);
    ~WebServer();  // stop()
    WebServer(const WebServer&) = delete;
    WebServer& operator=(const WebServer&) = delete;

    // Binds and starts the server's thread; the port bound (port 0: any), or nullopt with
    // `error` set to one line.
    std::optional<uint16_t> start(const std::string& bind_address, uint16_t port,
                                  std::string& error);
    // Sends one binary message to a WebSocket unless its unsent bytes exceed `max_buffered`
    // (a slow browser skips frames instead of queueing seconds of them); after a drop, deltas
    // are dropped too until a key message goes through. Thread-safe.
    void send(uint64_t client, std::shared_ptr<const std::string> message, std::size_t max_buffered,
              MessageKind kind = MessageKind::independent);
    // Closes a WebSocket (a malformed message, say). Thread-safe.
    void close(uint64_t client, const std::string& reason);
    // Stops accepting, closes every connection (bounded: 1 s), joins the thread. Idempotent.
    void stop();

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace pathfarm::coord
