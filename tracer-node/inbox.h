// What the coordinator sent a tracer, decoded on the network thread (each message parsed once)
// and queued for the worker; truncations and the newest commit are control, seen by the render
// in progress at once rather than after it.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/wire/messages.h"

namespace pathfarm::tracer {

class Inbox {
public:
    // Network thread: decodes and queues one envelope.
    void push(const std::string& envelope);
    // The session closed: pop() returns nothing once the queue is drained.
    void close();
    // The next message (an error if it did not decode); nothing when the session closed (after
    // draining) or stop was requested.
    std::optional<Result<wire::TracerInbound>> pop(const std::atomic<bool>& stop);
    // The newest commit announced: a render of an older frame can be abandoned.
    uint64_t newest_commit() const { return newest_commit_; }
    // Whether row y of assignment `a` went to another tracer (a truncation of its frame).
    bool truncated(const wire::Assignment& a, uint32_t y) const;

private:
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Result<wire::TracerInbound>> queue_;
    std::atomic<uint64_t> newest_commit_{0};
    uint64_t truncation_frame_ = 0;
    std::vector<uint32_t> truncations_;  // rows where this frame's assignments now end
    bool closed_ = false;
};

}  // namespace pathfarm::tracer
