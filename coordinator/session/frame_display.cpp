// The display thread: a queue of frames, shown one after another.
#include "coordinator/session/frame_display.h"

#include <spdlog/spdlog.h>

#include "common/film/image_io.h"
#include "coordinator/frame/parallel_image.h"
#include "coordinator/pacing/extra_samples.h"

namespace pathfarm::coord {

FrameDisplay::FrameDisplay(const FarmOptions& options, ClientHub& clients, FarmMetrics& metrics,
                           const Timer& clock)
    : o_(options),
      clients_(clients),
      metrics_(metrics),
      clock_(clock),
      arena_(options.display_threads > 0 ? options.display_threads
                                         : int(tbb::task_arena::automatic)),
      frame_stats_(options.stats_csv, kFrameStatsColumns),
      tracer_stats_(options.tracer_stats_csv, kTracerStatsColumns),
      costs_(options.record_costs, kUnitCostColumns),
      thread_([this] { run(); }) {}

FrameDisplay::~FrameDisplay() { finish(); }

void FrameDisplay::submit(DisplayJob job) {
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [&] { return queue_.empty(); });
    queue_.push_back(std::move(job));
    cv_.notify_all();
}

float FrameDisplay::min_history_frames() {
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [&] { return queue_.empty() && !busy_; });
    return o_.denoise ? denoiser_.min_history_frames() : accumulator_.min_history_frames();
}

std::vector<float> FrameDisplay::history_after(uint64_t frame) {
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [&] { return last_shown_ >= int64_t(frame) || (queue_.empty() && !busy_); });
    for (auto it = histories_.rbegin(); it != histories_.rend(); ++it)
        if (it->first <= frame) return it->second;
    return {};
}

void FrameDisplay::finish() {
    {
        std::lock_guard lock(mutex_);
        if (!thread_.joinable()) return;
        stopping_ = true;
        cv_.notify_all();
    }
    thread_.join();
}

void FrameDisplay::run() {
    for (;;) {
        std::unique_lock lock(mutex_);
        cv_.wait(lock, [&] { return !queue_.empty() || stopping_; });
        if (queue_.empty()) return;  // stopping, and everything shown
        DisplayJob job = std::move(queue_.front());
        queue_.pop_front();
        busy_ = true;
        cv_.notify_all();  // the loop may queue the next frame while this one is shown
        lock.unlock();
        arena_.execute([&] { show(job); });
        std::vector<float> history;
        if (o_.converge)
            history = o_.denoise ? denoiser_.history_frames() : accumulator_.history_frames();
        lock.lock();
        busy_ = false;
        last_shown_ = int64_t(job.work.frame);
        histories_.emplace_back(job.work.frame, std::move(history));
        if (histories_.size() > 3) histories_.pop_front();
        cv_.notify_all();
    }
}

// Upscale what workload scaling rendered smaller, converge, record, send, dump. A frame that
// rendered nothing (converged and unchanged) shows the converged image again. display_ms is
// all of it, on this thread.
void FrameDisplay::show(DisplayJob& job) {
    const Timer display_timer;
    const FrameWork& w = job.work;
    FloatImage image = job.rendered ? std::move(job.outcome.image)
                       : o_.denoise ? denoiser_.output()
                                    : accumulator_.output();
    if (image.width != o_.width || image.height != o_.height)
        image = resize_bilinear_parallel(image, o_.width, o_.height);
    ConvergeStats converged{0.0, 1.0, 0.0};
    double denoise_ms = 0.0;
    if ((o_.converge || o_.denoise) && job.rendered) {
        GBuffer spare =
            o_.denoise ? denoiser_.take_spare_gbuffer() : accumulator_.take_spare_gbuffer();
        job.view.gbuffer =
            gbuffer_from_first_hits(job.outcome.first_hits, w.width, w.height, job.view.camera,
                                    o_.width, o_.height, std::move(spare));
        if (w.extra_map && w.width == o_.width && w.height == o_.height)
            job.view.sample_weights = sample_weights(*w.extra_map, w.spp);
        if (o_.denoise) {
            const Timer denoise_timer;
            converged = denoiser_.filter(image, std::move(job.view), o_.converge);
            denoise_ms = denoise_timer.milliseconds();
        } else {
            converged = accumulator_.blend(image, std::move(job.view));
        }
    }
    clients_.send(image, {w.frame, w.width, w.height, job.rendered ? w.spp : 0});
    if (!o_.dump_frames.empty()) {
        const std::string path = fmt::format("{}/frame_{:06d}.pfm", o_.dump_frames, w.frame);
        if (Status s = write_image(path, image); !s) spdlog::error("{}", s.error().message);
    }
    record(job, converged, display_timer.milliseconds(), denoise_ms);
}

// The CSV rows, then the live metrics (so that /metrics never counts a frame the CSV has not).
void FrameDisplay::record(const DisplayJob& job, const ConvergeStats& converged, double display_ms,
                          double denoise_ms) {
    const FrameWork& w = job.work;
    const FrameOutcome& out = job.outcome;
    frame_stats_.row(w.frame, job.tracers, job.frame_ms, out.idle_pct, job.commit_bytes,
                     out.tile_bytes, job.rendered ? w.spp + w.extra : 0.0, w.rr_scale, w.width,
                     w.height, converged.mean_f, converged.kept, int(job.at_floor), display_ms,
                     clock_.milliseconds(), denoise_ms);
    FrameSample sample{job.rendered,     job.frame_ms,   job.tracers,
                       job.commit_bytes, out.tile_bytes, {}};
    for (const TracerFrameStats& t : out.tracers) {
        tracer_stats_.row(w.frame, t.name, t.first_range.y0, t.first_range.rows(), t.render_ms,
                          t.rows_delivered, t.update_ms);
        sample.per_tracer.push_back(
            {t.name, job.frame_ms > 0.0 ? t.render_ms / job.frame_ms : 0.0, t.rows_delivered});
    }
    for (std::size_t u = 0; u < out.units.size(); ++u)
        costs_.row(w.frame, u, out.units[u].us);
    metrics_.observe_frame(sample);
}

}  // namespace pathfarm::coord
