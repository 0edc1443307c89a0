// Tracer daemon: connects and reconnects; the network thread decodes into the inbox and this
// thread's FrameWorker applies commits and renders, so rendering never blocks the connection.
#include "tracer-node/tracer_daemon.h"

#include <thread>

#include <spdlog/spdlog.h>

#include "common/net/session.h"
#include "common/sampling/rng.h"
#include "tracer-node/backend/render_backend.h"
#include "tracer-node/frame_worker.h"
#include "tracer-node/inbox.h"

namespace pathfarm::tracer {
namespace {

// --slowdown's largest value: a machine a thousand times slower is as slow as a test needs.
constexpr double kMaxSlowdown = 1000.0;

// One connection's lifetime: messages until it closes or the replica needs a fresh snapshot.
void serve_session(const TracerOptions& o, RenderBackend& backend, net::Session& session,
                   Inbox& inbox, const std::atomic<bool>& stop) {
    FrameWorker worker(
        o, backend, [&session](std::string envelope) { session.send(std::move(envelope)); },
        RenderControl{
            [&inbox] { return inbox.newest_commit(); },
            [&inbox](const wire::Assignment& a, uint32_t y) { return inbox.truncated(a, y); }});
    while (auto message = inbox.pop(stop)) {
        Status s = *message ? worker.handle(**message) : Status(message->error());
        if (!s) {
            spdlog::error("{}; reconnecting for a fresh snapshot", s.error().message);
            break;
        }
    }
    session.close("tracer stopping");
}

}  // namespace

double frame_slowdown(const TracerOptions& o, uint64_t frame) {
    Pcg32 rng(frame, o.hiccup_seed);
    return rng.next_float() < o.hiccup_p ? 2.0 * o.slowdown : o.slowdown;
}

Status run_tracer(const TracerOptions& o, const std::atomic<bool>& stop) {
    auto kind = parse_backend_kind(o.backend);
    if (!kind) return kind.error();
    auto backend =
        create_backend(*kind, BackendOptions{o.threads, o.cl_platform, o.cl_device, o.texture_lod});
    if (!backend) return backend.error();
    // An infinite or huge slowdown slept forever (or overflowed the sleep's duration): the
    // coordinator saw a tracer that never answered, the tracer no error.
    if (!(o.slowdown >= 1.0 && o.slowdown <= kMaxSlowdown))
        return make_error(ErrorCode::invalid_argument, "--slowdown {}: must be in [1, {}]",
                          o.slowdown, kMaxSlowdown);
    if (!(o.hiccup_p >= 0.0 && o.hiccup_p <= 1.0))
        return make_error(ErrorCode::invalid_argument, "--hiccup-p {}: must be in [0, 1]",
                          o.hiccup_p);
    net::NetService net;
    net::ClientConfig config;
    config.host = o.host;
    config.port = o.port;
    config.secret = o.secret;
    config.tls = !o.insecure_plaintext;
    config.hello.role = net::PeerRole::tracer;
    config.hello.name = o.name;
    config.hello.backend = o.backend;
    config.hello.threads = uint32_t(o.threads);
    config.hello.wants_bvh_nodes = (*backend)->wants_bvh_nodes();
    auto backoff = std::chrono::milliseconds(200);
    for (int attempt = 0; !stop && (o.max_reconnects < 0 || attempt <= o.max_reconnects);
         ++attempt) {
        auto inbox = std::make_shared<Inbox>();  // handlers go in before the first message
        config.on_message = [inbox](std::string&& m) { inbox->push(m); };
        config.on_closed = [inbox](const std::string& reason) {
            spdlog::warn("coordinator connection closed: {}", reason);
            inbox->close();
        };
        auto session = net.connect_sync(config);
        if (!session) {
            // Giving up on a coordinator it cannot reach is a failure (a supervisor restarts
            // it); a session that ended with no reconnection left to try (--max-reconnects 0
            // after the coordinator finished) leaves the loop as the normal end.
            if (o.max_reconnects >= 0 && attempt == o.max_reconnects && !stop)
                return make_error(ErrorCode::io_error, "{} (gave up after {} connection attempt{})",
                                  session.error().message, attempt + 1, attempt == 0 ? "" : "s");
            spdlog::warn("{} (retrying in {} ms)", session.error().message, backoff.count());
            for (auto waited = std::chrono::milliseconds(0); waited < backoff && !stop;
                 waited += std::chrono::milliseconds(50))
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
            backoff = std::min(backoff * 2, std::chrono::milliseconds(5000));
            continue;
        }
        spdlog::info("connected to {}:{} as \"{}\"", o.host, o.port, o.name);
        backoff = std::chrono::milliseconds(200);
        serve_session(o, **backend, **session, *inbox, stop);
    }
    return {};
}

}  // namespace pathfarm::tracer
