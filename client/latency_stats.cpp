// Latency bookkeeping.
#include "client/latency_stats.h"

#include <algorithm>
#include <cmath>

namespace pathfarm::client {

double quantile(std::vector<double> values, double q) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const auto rank = std::size_t(std::ceil(q * double(values.size())));
    return values[std::min(values.size() - 1, rank > 0 ? rank - 1 : 0)];
}

Status LatencyStats::open_csv(const std::string& path) {
    csv_.open(path);
    if (!csv_) return make_error(ErrorCode::io_error, "--latency-csv {}: cannot write", path);
    csv_ << "frame,arrival_ms,interval_ms,inputs_acked,latency_ms\n";
    return {};
}

void LatencyStats::input_sent(uint64_t sequence, Clock::time_point at) { pending_[sequence] = at; }

void LatencyStats::frame_arrived(uint64_t frame, uint64_t last_input_sequence,
                                 Clock::time_point at) {
    if (!first_) first_ = at;
    double interval = 0.0;
    if (last_frame_) {
        interval = std::chrono::duration<double, std::milli>(at - *last_frame_).count();
        intervals_ms_.push_back(interval);
    }
    last_frame_ = at;
    int acked = 0;
    double newest_ms = 0.0;  // latency of the newest input this frame answers
    for (auto it = pending_.begin(); it != pending_.end() && it->first <= last_input_sequence;) {
        newest_ms = std::chrono::duration<double, std::milli>(at - it->second).count();
        latencies_ms_.push_back(newest_ms);
        ++acked;
        it = pending_.erase(it);
    }
    if (csv_.is_open()) {
        csv_ << frame << ',' << std::chrono::duration<double, std::milli>(at - *first_).count()
             << ',' << interval << ',' << acked << ',';
        if (acked > 0) csv_ << newest_ms;
        csv_ << '\n';
    }
}

LatencySummary LatencyStats::summary() const {
    return {latencies_ms_.size(),         intervals_ms_.size() + (first_ ? 1 : 0),
            quantile(latencies_ms_, 0.5), quantile(latencies_ms_, 0.99),
            quantile(intervals_ms_, 0.5), quantile(intervals_ms_, 0.99)};
}

}  // namespace pathfarm::client
