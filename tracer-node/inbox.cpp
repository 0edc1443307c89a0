// The tracer's inbox.
#include "tracer-node/inbox.h"

#include <algorithm>

namespace pathfarm::tracer {

void Inbox::push(const std::string& envelope) {
    auto message = wire::decode_for_tracer(envelope);
    std::lock_guard lock(mutex_);
    if (message) {
        if (const auto* c = std::get_if<wire::CommitPart>(&*message))
            newest_commit_ = std::max(newest_commit_.load(), c->frame);
        if (const auto* t = std::get_if<wire::Truncation>(&*message)) {
            if (t->frame != truncation_frame_) truncations_.clear();
            truncation_frame_ = t->frame;
            truncations_.push_back(t->row);
            return;  // control, not work
        }
    }
    queue_.push_back(std::move(message));
    cv_.notify_one();
}

void Inbox::close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
    cv_.notify_one();
}

std::optional<Result<wire::TracerInbound>> Inbox::pop(const std::atomic<bool>& stop) {
    std::unique_lock lock(mutex_);
    while (queue_.empty() && !closed_ && !stop)
        cv_.wait_for(lock, std::chrono::milliseconds(100));
    if (queue_.empty()) return std::nullopt;
    auto message = std::move(queue_.front());
    queue_.pop_front();
    return message;
}

bool Inbox::truncated(const wire::Assignment& a, uint32_t y) const {
    std::lock_guard lock(mutex_);
    if (a.frame != truncation_frame_) return false;
    return std::any_of(truncations_.begin(), truncations_.end(),
                       [&](uint32_t at) { return a.y0 < at && at < a.y1 && at <= y; });
}

}  // namespace pathfarm::tracer
