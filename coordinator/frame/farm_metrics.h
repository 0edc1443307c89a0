// The farm's live figures for operators: what the stats CSVs record per frame, kept as
// Prometheus counters, gauges and histograms and rendered in the text exposition format for
// the HTTP port's /metrics (docs/web.md lists them). Thread-safe: the display thread observes,
// the HTTP thread renders.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace pathfarm::coord {

// Cumulative buckets in seconds, Prometheus style (the +Inf bucket is the count).
class Histogram {
public:
    explicit Histogram(std::vector<double> upper_bounds);
    void observe(double seconds);
    // "# TYPE name histogram" and its _bucket, _sum and _count lines.
    void render(std::string& out, const std::string& name, const std::string& help) const;

private:
    std::vector<double> bounds_;
    std::vector<uint64_t> counts_;  // per bucket, not cumulative
    double sum_ = 0.0;
    uint64_t count_ = 0;
};

struct TracerSample {
    std::string name;
    double busy_fraction = 0.0;  // its render time over the frame's time
    int rows = 0;                // rows it delivered in the frame
};

struct FrameSample {
    bool rendered = true;  // false: converged and unchanged, nothing rendered
    double frame_ms = 0.0;
    std::size_t tracers = 0, commit_bytes = 0, tile_bytes = 0;
    std::vector<TracerSample> per_tracer;
};

class FarmMetrics {
public:
    FarmMetrics();
    void observe_frame(const FrameSample& frame);  // after the frame's CSV row is written
    void observe_input_latency(double seconds);    // input received -> frame showing it sent
    void add_client_bytes(std::size_t bytes);      // encoded frames handed to clients
    void set_clients(std::size_t native, std::size_t browser);
    std::string text() const;  // the exposition format, version 0.0.4

private:
    mutable std::mutex mutex_;
    uint64_t frames_ = 0;
    Histogram frame_time_, input_latency_;
    std::size_t tracers_ = 0, native_clients_ = 0, browser_clients_ = 0;
    uint64_t commit_bytes_ = 0, tile_bytes_ = 0, client_bytes_ = 0;
    struct PerTracer {
        double busy_fraction = 0.0;
        uint64_t rows = 0;
    };
    std::map<std::string, PerTracer> per_tracer_;  // every tracer name seen
};

// A label value escaped for the text format (backslash, double quote, newline).
std::string escape_label(const std::string& value);

}  // namespace pathfarm::coord
