// The farm's tracers (DESIGN.md, "The frame" steps 4-5): who is connected, which commit each
// replica holds, the rows of the frame each was given, the tiles that came back, rows re-issued
// when they are late or their tracer left, and rows taken mid-frame by a tracer that ran out
// (coordinator/balance/steal.h). Thread-safe: the network thread adds sessions and delivers
// their messages; the frame loop drives one frame at a time. Sockets are not needed: a tracer
// is any net::Session, so tests drive the pool with in-memory sessions.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/film/film.h"
#include "common/net/session.h"
#include "common/wire/light_sampling.h"
#include "coordinator/balance/balancer.h"
#include "coordinator/balance/unit_costs.h"
#include "coordinator/frame/frame_assembler.h"

namespace pathfarm::coord {

// The frame to render and its quality (workload scaling changes size, spp and roulette).
struct FrameWork {
    uint64_t frame = 0;
    int width = 0, height = 0, spp = 1;
    float rr_scale = 1.0f;
    uint32_t seed = 0;
    int max_depth = 8;
    bool first_hits = false;  // the tiles carry first hits (FrameOutcome::first_hits)
    wire::LightSampling light_sampling = wire::LightSampling::power;
    // Samples beyond spp (coordinator/pacing/extra_samples.h): their mean per pixel, the map
    // (converging weighs each pixel by it) and its wire form (common/film/
    // extra_samples_codec.h); null and empty: none.
    double extra = 0.0;
    std::shared_ptr<const std::vector<uint8_t>> extra_map{};
    std::string extra_samples_zstd{};
};

// A commit as envelopes, plain and with the BVH ops for tracers that traverse the
// coordinator's BVH, and a snapshot maker for tracers whose replica is not at the last commit.
struct FrameCommit {
    const std::vector<std::string>* plain = nullptr;
    const std::vector<std::string>* with_bvh = nullptr;
    std::function<std::vector<std::string>(bool with_bvh)> snapshot;
    // The snapshot still describes this frame while it renders (the real-time loop prepares
    // the next frame only after this one): tracers that join mid-frame can then take over a
    // frame whose every tracer left, instead of the frame being skipped. The pool keeps
    // `snapshot` for the frame (plain and with_bvh only during begin()).
    bool snapshot_during_frame = false;
};

// One tracer's part in a finished frame (the tracer statistics CSV).
struct TracerFrameStats {
    std::string name;
    RowRange first_range;
    double render_ms = 0.0;
    int rows_delivered = 0;
    double update_ms = 0.0;      // replica and backend update before rendering
    bool from_snapshot = false;  // its replica was rebuilt from a snapshot for this frame
};

// What a finished frame leaves: its image and the tracers' accounting.
struct FrameOutcome {
    FloatImage image;
    std::vector<FirstHit> first_hits;  // at the image's size, by commit instance id; if asked
    double idle_pct = 0.0;
    std::size_t tile_bytes = 0;
    std::vector<TracerFrameStats> tracers;
    std::vector<UnitReport> units;  // per work unit (--record-costs)
};

class TracerPool {
public:
    using Clock = std::chrono::steady_clock;
    // `now` paces the steal rule (how long ago each tracer was last heard of); tests pass a
    // clock of their own. Deadlines always use the steady clock.
    TracerPool(std::unique_ptr<Balancer> balancer, std::chrono::milliseconds deadline,
               std::function<Clock::time_point()> now = Clock::now);

    // --- network thread
    // Takes a tracer's session and installs its message and close handlers.
    void add(std::shared_ptr<net::Session> session);

    // --- frame loop
    // Waits until at least `count` tracers are connected; false when `stop` was set.
    bool wait_for(std::size_t count, const std::atomic<bool>& stop);
    // Starts frame `work`: every tracer's replica is brought to its commit (or a snapshot) and,
    // unless `render` is false (nothing to render: the replicas only follow), rows are split.
    void begin(const FrameWork& work, const FrameCommit& commit, bool render);
    enum class Wait { complete, abandoned, stopped };
    // Until every row arrived. Rows still missing at the deadline are re-issued to idle
    // tracers. When every tracer of the frame left, the tracers there now (or the next to
    // join) get a snapshot of it and its missing rows if the commit allows it
    // (snapshot_during_frame); otherwise the frame is abandoned.
    Wait wait_for_frame(const std::atomic<bool>& stop);
    // The finished frame; feeds what the tracers delivered to the balancer for the next one.
    FrameOutcome finish();
    std::size_t size() const;
    // No tracer is accepted from now on; returns the sessions for the caller to close.
    std::vector<std::shared_ptr<net::Session>> stop_accepting();

private:
    struct Tracer {
        std::shared_ptr<net::Session> session;
        std::string name;
        bool wants_bvh = false;
        std::optional<uint64_t> replica_commit;  // the commit its replica holds once sent
        std::vector<RowRange> assigned;          // this frame
        RowRange first_assignment;
        double render_ms = 0.0;                     // this frame, from its tiles
        double update_ms = 0.0;                     // this frame's update, from its tiles
        bool from_snapshot = false;                 // this frame's replica: from a snapshot
        int tile_rows = 0;                          // rows of those tiles
        Clock::time_point news_at;                  // its last tile or assignment
        std::optional<Clock::time_point> stole_at;  // when it last took rows (for the log)
        std::optional<uint64_t> measured_frame;     // the frame `measured` describes
        TracerFrame measured;                       // what the balancer hears of that frame
    };
    void on_tile(uint64_t id, const std::string& bytes);
    void on_closed(uint64_t id);
    void sync(Tracer& t, const FrameCommit& commit,
              std::optional<std::vector<std::string>> snapshots[2]);
    void split_rows(const std::vector<uint64_t>& ids);
    void assign(uint64_t id, Tracer& t, const RowRange& r);
    void reissue(const std::vector<RowRange>& ranges, bool idle_only);
    void steal_for(uint64_t id);
    void drop_silent();
    bool adopt_frame();
    bool idle(const Tracer& t) const;
    std::vector<RowRange> missing_of(const Tracer& t) const;

    std::unique_ptr<Balancer> balancer_;
    std::chrono::milliseconds deadline_;
    std::function<Clock::time_point()> now_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::map<uint64_t, Tracer> tracers_;
    bool accepting_ = true;
    FrameWork work_;
    FrameCommit commit_;  // this frame's: only its snapshot is used after begin()
    std::optional<FrameAssembler> assembler_;
    std::vector<UnitReport> units_;       // this frame
    std::vector<double> last_unit_cost_;  // last frame's cost map
    std::size_t tile_bytes_ = 0;
};

}  // namespace pathfarm::coord
