// The coordinator's HTTP port put together (docs/web.md): the server (web_server.h), its routes
// and token (http_routes.h), /metrics from the farm's metrics, and the browsers' WebSockets
// handed to the client hub as clients (inputs in, frames out).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "common/base/result.h"
#include "common/base/timer.h"
#include "coordinator/game/game.h"
#include "coordinator/http/http_routes.h"
#include "coordinator/http/web_server.h"

namespace pathfarm::coord {

class FarmMetrics;

struct BrowserEvents {  // called on the HTTP thread
    // `h264`: the page asked for H.264 (/ws?codec=h264: it has a WebCodecs decoder for it).
    std::function<void(uint64_t browser, bool h264)> joined;
    std::function<void(uint64_t browser)> left;
    std::function<void(uint64_t browser)> needs_key;  // a delta was dropped
    std::function<void(uint64_t browser, const PlayerInput&)> input;
};

class WebPort {
public:
    // tls: HTTPS and WSS with the operator's certificate (--https-cert, --https-key).
    WebPort(std::string token, const FarmMetrics& metrics, BrowserEvents events,
            std::optional<TlsFiles> tls = std::nullopt);
    ~WebPort();
    // The port bound; the URL to print is url(host).
    Result<uint16_t> start(const std::string& bind_address, uint16_t port);
    std::string url(const std::string& host) const;
    // One message to a browser (dropped while it still has much unsent; see WebServer::send).
    void send(uint64_t browser, std::shared_ptr<const std::string> message, MessageKind kind);
    uint64_t clock_us() const { return uint64_t(clock_.seconds() * 1e6); }
    void stop();  // closes every browser, bounded

private:
    void on_message(uint64_t browser, const std::string& bytes);

    std::string token_;
    BrowserEvents events_;
    HttpRoutes routes_;
    Timer clock_;
    uint16_t port_ = 0;
    bool https_ = false;
    std::unique_ptr<WebServer> server_;  // last: its thread calls into the members above
};

}  // namespace pathfarm::coord
