// The display stage of the farm's frame loop (DESIGN.md, "The frame" step 6), on a thread of
// its own: upscale what workload scaling rendered smaller, build the G-buffer from the first
// hits and converge, write the statistics, encode and send to every client, dump. It runs
// while the frame loop already starts the next frame, so the coordinator's own per-frame work
// is off the tracers' critical path. Frames are shown in the order they are submitted.
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>

#include <tbb/task_arena.h>

#include "common/base/timer.h"
#include "coordinator/converge/denoiser.h"
#include "coordinator/converge/temporal_accumulator.h"
#include "coordinator/frame/farm_stats.h"
#include "coordinator/session/client_hub.h"
#include "coordinator/session/farm_coordinator.h"
#include "coordinator/session/tracer_pool.h"

namespace pathfarm::coord {

// One frame to show, with everything the display needs of the loop's state at the time.
struct DisplayJob {
    FrameWork work;         // what was rendered (size, spp, extra samples, roulette)
    FrameView view;         // camera, instances, cut; its G-buffer is made from the first hits
    FrameOutcome outcome;   // the tiles' image, first hits and statistics
    bool rendered = true;   // false: converged and unchanged, the last output again
    double frame_ms = 0.0;  // assignment to last tile
    std::size_t tracers = 0, commit_bytes = 0;
    bool at_floor = false;  // workload scaling at its floor
};

class FrameDisplay {
public:
    // `clock` gives the stats' wall_ms; it and `clients` outlive the display.
    FrameDisplay(const FarmOptions& options, ClientHub& clients, FarmMetrics& metrics,
                 const Timer& clock);
    ~FrameDisplay();  // finishes what was submitted

    // Queues a frame; waits while the previous one is still queued (one shown, one waiting).
    void submit(DisplayJob job);
    // Least frames of history over the pixels once every submitted frame is shown.
    float min_history_frames();
    // Each pixel's frames of history as frame `frame` left it (waiting until it is shown), or
    // as the last frame shown before it left it when `frame` was never submitted; empty
    // without converging. The same whatever the display thread did since.
    std::vector<float> history_after(uint64_t frame);
    void finish();  // shows what was submitted and stops the thread

private:
    void run();
    void show(DisplayJob& job);
    void record(const DisplayJob& job, const ConvergeStats& converged, double display_ms,
                double denoise_ms);

    const FarmOptions& o_;
    ClientHub& clients_;
    FarmMetrics& metrics_;
    const Timer& clock_;
    TemporalAccumulator accumulator_;  // converging without the denoiser
    Denoiser denoiser_;                // converging (temporal) or not, with it
    tbb::task_arena arena_;            // FarmOptions::display_threads
    CsvWriter frame_stats_, tracer_stats_, costs_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<DisplayJob> queue_;
    bool busy_ = false, stopping_ = false;
    int64_t last_shown_ = -1;  // the frame number last shown
    // The history lengths the last few frames shown left, by frame number (history_after).
    std::deque<std::pair<uint64_t, std::vector<float>>> histories_;
    std::thread thread_;  // last: starts once everything above exists
};

}  // namespace pathfarm::coord
