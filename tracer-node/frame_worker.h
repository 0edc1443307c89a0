// The tracer's work on one connection (DESIGN.md, "The frame" step 5): keeps a replica in step
// with the coordinator's commits, hands the backend the scene and what changed, renders the
// rows it is assigned in tiles, each 4-row unit timed for the balancer (in one parallel call
// per tile where the backend times units itself, else one call per unit), and sends them
// (encoded beside the next tile's render, all sent before handle() returns). No sockets:
// messages come in decoded, tiles go out through a callback, so tests drive it directly.
#pragma once

#include <functional>
#include <string>

#include "common/base/result.h"
#include "common/wire/messages.h"
#include "tracer-node/backend/render_backend.h"
#include "tracer-node/replica/replica.h"
#include "tracer-node/tile_sender.h"
#include "tracer-node/tracer_daemon.h"

namespace pathfarm::tracer {

// What the render in progress checks between units (the inbox, in the daemon).
struct RenderControl {
    std::function<uint64_t()> newest_commit;  // a newer frame was announced: stop
    std::function<bool(const wire::Assignment&, uint32_t row)> truncated;  // rows went elsewhere
};

class FrameWorker {
public:
    using Send = TileSender::Send;
    FrameWorker(const TracerOptions& options, RenderBackend& backend, Send send,
                RenderControl control);

    // Handles one message; an error means the session must be dropped and re-synchronised.
    Status handle(const wire::TracerInbound& message);
    const Replica& replica() const { return replica_; }

private:
    Status render(const wire::Assignment& a);
    Status update_backend();
    Status render_tile(const wire::Assignment& a, RenderJob& job, int y0, int y1);
    Status render_tile_at_once(const wire::Assignment& a, RenderJob& job, int y0, int y1,
                               std::vector<float>& rgb, wire::Tile& tile);
    Status render_tile_by_units(const wire::Assignment& a, RenderJob& job, int y0, int y1,
                                double slowdown, std::vector<float>& rgb, wire::Tile& tile);
    std::vector<MeshBvhView> mesh_bvhs() const;
    void mark_deformed(const SceneChanges& changes);

    const TracerOptions& options_;
    RenderBackend& backend_;
    RenderControl control_;
    Replica replica_;
    SceneModel scene_;        // what the backend renders; outlives its use by the backend
    double update_ms_ = 0.0;  // this frame's replica and backend update, sent with its first tile
    std::vector<uint8_t> deformed_;  // per scene_ instance: its vertices changed in this commit
    TileSender sender_;              // last: its thread stops (sending what is queued) first
};

}  // namespace pathfarm::tracer
