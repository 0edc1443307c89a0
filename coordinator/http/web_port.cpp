// Wiring of the HTTP port: routes and WebSocket events to the farm.
#include "coordinator/http/web_port.h"

#include <spdlog/spdlog.h>

#include "coordinator/frame/farm_metrics.h"
#include "coordinator/http/web_protocol.h"

namespace pathfarm::coord {
namespace {
// A browser with this much unsent (several frames) gets no more until it has taken them:
// frames are skipped, never queued (a queue is latency).
constexpr std::size_t kMaxUnsentBytes = 256 * 1024;
}  // namespace

WebPort::WebPort(std::string token, const FarmMetrics& metrics, BrowserEvents events,
                 std::optional<TlsFiles> tls)
    : token_(std::move(token)),
      events_(std::move(events)),
      routes_(token_, [&metrics] { return metrics.text(); }) {
    WebServerHandlers h;
    h.on_http = [this](const HttpRequest& r) { return routes_.handle(r); };
    h.on_upgrade = [this](const HttpRequest& r) { return routes_.upgrade(r); };
    h.on_open = [this](uint64_t id, const HttpRequest& upgrade) {
        const bool h264 = query_value(upgrade.resource, "codec") == "h264";
        spdlog::info("browser {} joined ({})", id, h264 ? "H.264" : "JPEG");
        events_.joined(id, h264);
    };
    h.on_dropped = [this](uint64_t id) { events_.needs_key(id); };
    h.on_close = [this](uint64_t id) {
        spdlog::info("browser {} left", id);
        events_.left(id);
    };
    h.on_message = [this](uint64_t id, const std::string& bytes) { on_message(id, bytes); };
    https_ = tls.has_value();
    server_ = std::make_unique<WebServer>(std::move(h), std::move(tls));
}

WebPort::~WebPort() { stop(); }

Result<uint16_t> WebPort::start(const std::string& bind_address, uint16_t port) {
    std::string error;
    const std::optional<uint16_t> bound = server_->start(bind_address, port, error);
    if (!bound) return make_error(ErrorCode::io_error, "{}", error);
    port_ = *bound;
    return *bound;
}

std::string WebPort::url(const std::string& host) const {
    return fmt::format("{}://{}:{}/?token={}", https_ ? "https" : "http", host, port_, token_);
}

void WebPort::send(uint64_t browser, std::shared_ptr<const std::string> message, MessageKind kind) {
    server_->send(browser, std::move(message), kMaxUnsentBytes, kind);
}

void WebPort::on_message(uint64_t browser, const std::string& bytes) {
    auto input = decode_web_input(bytes);
    if (!input) {
        spdlog::warn("browser {}: {}", browser, input.error().message);
        server_->close(browser, input.error().message);
        return;
    }
    events_.input(browser, *input);
}

void WebPort::stop() { server_->stop(); }

}  // namespace pathfarm::coord
