// The coordinator's per-frame preparation.
#include "coordinator/frame/frame_pipeline.h"

#include <spdlog/spdlog.h>

#include "common/base/timer.h"
#include "coordinator/commit/bvh_ops.h"
#include "coordinator/commit/commit_builder.h"

namespace pathfarm::coord {

FramePipeline::FramePipeline(SceneModel scene, const PipelineOptions& options)
    : graph_(std::move(scene)), accel_(options.rebuild_factor) {
    if (options.clip) graph_.set_playing_clip(*options.clip);
}

Status FramePipeline::start_game(const std::string& kind, const std::string& scene_name) {
    auto g = make_game(kind, scene_name, graph_);
    if (!g) return g.error();
    game_ = std::move(*g);
    spdlog::info("game: {}", game_->name());
    return {};
}

FrameUpdate FramePipeline::advance(uint64_t frame, double clock,
                                   const std::vector<PlayerInput>& inputs) {
    FrameUpdate u;
    u.frame = frame;
    Timer timer;
    if (game_) {
        for (const PlayerInput& in : inputs) {  // input takes effect at frame boundaries
            game_->on_input(in, clock, graph_, queries_);
            last_applied_input_ = std::max(last_applied_input_, in.sequence);
        }
        game_->update(clock, graph_);
    }
    graph_.advance(clock);
    u.animate_ms = timer.milliseconds();
    u.changes = graph_.take_changes();
    timer.reset();
    u.previous = accel_snapshot_;
    accel_snapshot_ = frame == 0 ? accel_.build(graph_.state(), frame)
                                 : accel_.update(graph_.state(), u.changes, frame);
    queries_.publish(accel_snapshot_);
    u.accel_ms = timer.milliseconds();
    u.accel = accel_snapshot_;
    u.unchanged = frame > 0 && u.changes.empty();
    u.last_input_sequence = last_applied_input_;
    return u;
}

Commit FramePipeline::commit(const FrameUpdate& u, bool with_bvh) const {
    Commit c = build_commit(graph_.state(), u.changes, u.frame, u.frame == 0 ? 0 : u.frame - 1);
    if (with_bvh)
        for (CommitOp& op : build_bvh_ops(u.previous.get(), *u.accel))
            c.ops.push_back(std::move(op));
    return c;
}

Commit FramePipeline::snapshot(uint64_t frame, bool with_bvh) const {
    Commit c = make_snapshot(graph_.state(), frame);
    if (with_bvh)
        for (CommitOp& op : build_bvh_ops(nullptr, *accel_snapshot_))
            c.ops.push_back(std::move(op));
    return c;
}

FrameView FramePipeline::view(const FrameUpdate& u) const {
    FrameView v;
    const SceneState& state = graph_.state();
    if (const auto cam = state.cameras.find(state.active_camera); cam != state.cameras.end())
        v.camera = cam->second;
    for (const InstanceAccel& inst : u.accel->instances)
        v.instances[inst.id] = inst.to_world;
    // Deformed instances and their vertices now, one copy per mesh however many show it.
    std::map<uint32_t, std::shared_ptr<const SurfaceVertices>> by_mesh;
    for (const auto& [id, inst] : state.instances) {
        if (!u.changes.vertices_changed.count(inst.mesh)) continue;
        v.deformed.insert(id);
        auto& surface = by_mesh[inst.mesh];
        if (!surface)
            if (const auto mesh = state.meshes.find(inst.mesh); mesh != state.meshes.end())
                surface = std::make_shared<const SurfaceVertices>(
                    SurfaceVertices{mesh->second.positions, mesh->second.indices});
        if (surface) v.surfaces[id] = surface;
    }
    // What lights the scene changed: the history of every pixel is wrong.
    v.cut = !u.changes.materials_set.empty() || !u.changes.materials_removed.empty() ||
            !u.changes.textures_set.empty() || u.changes.environment;
    return v;
}

}  // namespace pathfarm::coord
