// Prometheus text exposition (https://prometheus.io/docs/instrumenting/exposition_formats/),
// written here: a few dozen lines of text need no client library.
#include "coordinator/frame/farm_metrics.h"

#include <algorithm>

#include <fmt/format.h>

namespace pathfarm::coord {
namespace {

void header(std::string& out, const std::string& name, const char* type, const std::string& help) {
    out += fmt::format("# HELP {} {}\n# TYPE {} {}\n", name, help, name, type);
}

template <typename T>
void single(std::string& out, const std::string& name, const char* type, const std::string& help,
            T value) {
    header(out, name, type, help);
    out += fmt::format("{} {}\n", name, value);
}

}  // namespace

Histogram::Histogram(std::vector<double> upper_bounds)
    : bounds_(std::move(upper_bounds)), counts_(bounds_.size() + 1, 0) {}

void Histogram::observe(double seconds) {
    const auto at = std::lower_bound(bounds_.begin(), bounds_.end(), seconds) - bounds_.begin();
    ++counts_[std::size_t(at)];
    sum_ += seconds;
    ++count_;
}

void Histogram::render(std::string& out, const std::string& name, const std::string& help) const {
    header(out, name, "histogram", help);
    uint64_t cumulative = 0;
    for (std::size_t b = 0; b < bounds_.size(); ++b) {
        cumulative += counts_[b];
        out += fmt::format("{}_bucket{{le=\"{}\"}} {}\n", name, bounds_[b], cumulative);
    }
    out += fmt::format("{}_bucket{{le=\"+Inf\"}} {}\n", name, count_);
    out += fmt::format("{}_sum {}\n{}_count {}\n", name, sum_, name, count_);
}

std::string escape_label(const std::string& value) {
    std::string out;
    for (const char c : value) {
        if (c == '\\' || c == '"') out += '\\';
        if (c == '\n') {
            out += "\\n";
            continue;
        }
        out += c;
    }
    return out;
}

FarmMetrics::FarmMetrics()
    : frame_time_({0.01, 0.02, 0.033, 0.05, 0.067, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0, 2.0}),
      input_latency_({0.025, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0, 2.0}) {}

void FarmMetrics::observe_frame(const FrameSample& f) {
    std::lock_guard lock(mutex_);
    ++frames_;
    tracers_ = f.tracers;
    commit_bytes_ += f.commit_bytes;
    tile_bytes_ += f.tile_bytes;
    if (!f.rendered) return;
    frame_time_.observe(f.frame_ms / 1000.0);
    // A tracer that rendered nothing in this frame (the others took its rows) is idle in it,
    // and its row counter goes on: a counter never goes back.
    for (auto& [name, p] : per_tracer_)
        p.busy_fraction = 0.0;
    for (const TracerSample& t : f.per_tracer) {
        PerTracer& p = per_tracer_[t.name];
        p.busy_fraction = t.busy_fraction;
        p.rows += uint64_t(t.rows);
    }
}

void FarmMetrics::observe_input_latency(double seconds) {
    std::lock_guard lock(mutex_);
    input_latency_.observe(seconds);
}

void FarmMetrics::add_client_bytes(std::size_t bytes) {
    std::lock_guard lock(mutex_);
    client_bytes_ += bytes;
}

void FarmMetrics::set_clients(std::size_t native, std::size_t browser) {
    std::lock_guard lock(mutex_);
    native_clients_ = native;
    browser_clients_ = browser;
}

std::string FarmMetrics::text() const {
    std::lock_guard lock(mutex_);
    std::string out;
    single(out, "pathfarm_frames_total", "counter", "Frames shown to clients.", frames_);
    frame_time_.render(out, "pathfarm_frame_seconds",
                       "Rendered frames' time from assignment to the last tile.");
    single(out, "pathfarm_tracers", "gauge", "Tracers rendering the last frame.", tracers_);
    header(out, "pathfarm_tracer_busy_ratio", "gauge",
           "Each tracer's render time over the last rendered frame's time.");
    for (const auto& [name, t] : per_tracer_)
        out += fmt::format("pathfarm_tracer_busy_ratio{{tracer=\"{}\"}} {}\n", escape_label(name),
                           t.busy_fraction);
    header(out, "pathfarm_tracer_rows_total", "counter",
           "Rows each tracer (by name) delivered since the coordinator started.");
    for (const auto& [name, t] : per_tracer_)
        out += fmt::format("pathfarm_tracer_rows_total{{tracer=\"{}\"}} {}\n", escape_label(name),
                           t.rows);
    single(out, "pathfarm_commit_bytes_total", "counter",
           "Commit bytes prepared for the tracers (one copy per frame).", commit_bytes_);
    single(out, "pathfarm_tile_bytes_total", "counter", "Tile bytes received from tracers.",
           tile_bytes_);
    single(out, "pathfarm_client_frame_bytes_total", "counter",
           "Encoded frame bytes handed to clients.", client_bytes_);
    header(out, "pathfarm_clients", "gauge", "Connected clients by kind.");
    out += fmt::format("pathfarm_clients{{kind=\"native\"}} {}\n", native_clients_);
    out += fmt::format("pathfarm_clients{{kind=\"browser\"}} {}\n", browser_clients_);
    input_latency_.render(out, "pathfarm_input_latency_seconds",
                          "From an input's arrival to the frame that shows it being sent.");
    return out;
}

}  // namespace pathfarm::coord
