// The tile sender's thread (tile_sender.h).
#include "tracer-node/tile_sender.h"

#include <utility>

#include "common/base/timer.h"
#include "common/film/float_codec.h"

namespace pathfarm::tracer {

TileSender::TileSender(Send send) : send_(std::move(send)), thread_([this] { run(); }) {}

TileSender::~TileSender() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    work_.notify_one();
    thread_.join();
}

void TileSender::submit(Job job) {
    {
        std::lock_guard lock(mutex_);
        jobs_.push_back(std::move(job));
    }
    work_.notify_one();
}

void TileSender::flush() {
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return jobs_.empty() && !busy_; });
}

void TileSender::run() {
    std::unique_lock lock(mutex_);
    for (;;) {
        work_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
        if (jobs_.empty()) return;  // stopping, and nothing left to send
        Job job = std::move(jobs_.front());
        jobs_.pop_front();
        busy_ = true;
        lock.unlock();
        // The tile's time stays the tracer's whole work for it (stats: utilisation, and the
        // workload scaler's part that grows with the pixels), as when it encoded inline.
        const Timer encoding;
        job.tile.rgb_zstd = compress_floats(job.rgb.data(), job.rgb.size());
        if (!job.hits.empty())
            job.tile.first_hits_zstd = encode_first_hits(job.hits.data(), job.hits.size());
        job.tile.render_ms += encoding.milliseconds();
        send_(wire::encode_tile(job.tile));
        lock.lock();
        busy_ = false;
        if (jobs_.empty()) done_.notify_all();
    }
}

}  // namespace pathfarm::tracer
