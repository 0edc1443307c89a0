// The tracer's frame work: commits to the replica, the change set to the backend, rows to tiles.
#include "tracer-node/frame_worker.h"

#include <algorithm>
#include <thread>
#include <utility>

#include "common/base/timer.h"
#include "common/base/work_unit.h"
#include "common/film/extra_samples_codec.h"
#include "common/film/first_hits.h"

namespace pathfarm::tracer {

FrameWorker::FrameWorker(const TracerOptions& options, RenderBackend& backend, Send send,
                         RenderControl control)
    : options_(options),
      backend_(backend),
      control_(std::move(control)),
      sender_(std::move(send)) {}

Status FrameWorker::handle(const wire::TracerInbound& message) {
    if (const auto* chunk = std::get_if<wire::ChunkPart>(&message)) {
        replica_.add_chunk(chunk->frame, chunk->parsed);
        return {};
    }
    if (const auto* commit = std::get_if<wire::CommitPart>(&message))
        return replica_.apply(*commit->parsed, commit->frame);
    if (const auto* a = std::get_if<wire::Assignment>(&message)) return render(*a);
    return {};  // truncations are the inbox's
}

// The coordinator's mesh BVHs in SceneModel mesh order (to_scene_model keeps id order).
std::vector<MeshBvhView> FrameWorker::mesh_bvhs() const {
    std::vector<MeshBvhView> views;
    const ReplicaState& state = replica_.state();
    for (const auto& [id, mesh] : state.scene.meshes) {
        const auto it = state.bvh.meshes.find(id);
        views.push_back(it == state.bvh.meshes.end()
                            ? MeshBvhView{}
                            : MeshBvhView{&it->second.nodes, &it->second.prim_indices});
    }
    return views;
}

Status FrameWorker::update_backend() {
    const glm::dvec3 previous_origin = scene_.origin;
    SceneChanges changes = replica_.update_scene(scene_);
    // Camera-relative, as pathfarm-render does (scene_model.h): same floats, same image. A
    // camera move into another cell shifts every instance the backend sees; within its cell
    // it moves only the camera.
    recentre_for_backend(scene_, previous_origin, changes);
    mark_deformed(changes);
    if (backend_.wants_bvh_nodes()) backend_.provide_mesh_bvhs(mesh_bvhs());
    return backend_.update_scene(scene_, changes);
}

// Instances whose mesh's vertices this commit changed: their first hits carry the triangle
// and barycentrics (first_hits.h), which the coordinator needs to reproject them. Kept until
// the next scene change (a later assignment of the same commit needs them too); a commit that
// changes nothing keeps the last one's, a few bytes more that the coordinator ignores: it reads
// them only for instances its own view says deformed.
void FrameWorker::mark_deformed(const SceneChanges& changes) {
    std::vector<uint8_t> mesh_deformed(scene_.meshes.size(), changes.structure ? 1 : 0);
    for (const uint32_t m : changes.mesh_vertices)
        if (m < mesh_deformed.size()) mesh_deformed[m] = 1;
    deformed_.assign(scene_.instances.size(), 0);
    for (std::size_t i = 0; i < scene_.instances.size(); ++i) {
        const int mesh = scene_.instances[i].mesh;
        deformed_[i] = mesh >= 0 && std::size_t(mesh) < mesh_deformed.size() && mesh_deformed[mesh];
    }
}

Status FrameWorker::render(const wire::Assignment& a) {
    if (!replica_.initialised() || a.commit != replica_.commit())
        return make_error(ErrorCode::invalid_argument,
                          "assignment for commit {} but the replica holds {}", a.commit,
                          replica_.commit());
    const Timer update;
    if (replica_.scene_changed())
        if (Status s = update_backend(); !s) return s;
    update_ms_ += update.milliseconds();
    RenderJob job;
    job.frame = FrameSpec{int(a.width),
                          int(a.height),
                          uint32_t(a.frame),
                          a.seed,
                          int(a.spp),
                          0,
                          scene_.cameras.empty() ? Camera{} : scene_.cameras[0]};
    std::vector<uint8_t> extra;  // outlives the job's rendering
    if (!a.extra_samples_zstd.empty()) {
        auto map = decode_extra_samples(a.extra_samples_zstd, int(a.width), int(a.height));
        if (!map)
            return make_error(ErrorCode::parse_error, "assignment of frame {}: {}", a.frame,
                              map.error().message);
        extra = std::move(*map);
        job.frame.extra_samples = extra.data();
    }
    job.integrator.max_depth = int(a.max_depth);
    job.integrator.rr_scale = std::min(1.0f, a.rr_scale);
    job.integrator.light_selection =
        a.light_sampling == wire::LightSampling::tree        ? LightSelection::tree
        : a.light_sampling == wire::LightSampling::automatic ? LightSelection::automatic
                                                             : LightSelection::power;
    const int tile_rows = kRowsPerTile;
    Status result;
    for (int y = int(a.y0); y < int(a.y1); y += tile_rows) {
        if (control_.newest_commit() > a.commit) break;  // the frame closed: drop stale rows
        if (control_.truncated(a, uint32_t(y))) break;   // the rest went to another tracer
        if (Status s = render_tile(a, job, y, std::min(int(a.y1), y + tile_rows)); !s) {
            result = s;
            break;
        }
    }
    sender_.flush();  // every tile of the assignment is sent when handle() returns
    return result;
}

Status FrameWorker::render_tile(const wire::Assignment& a, RenderJob& job, int y0, int y1) {
    std::vector<float> rgb(std::size_t(y1 - y0) * a.width * 3);
    std::vector<FirstHit> hits(a.first_hits ? std::size_t(y1 - y0) * a.width : 0);
    job.first_hits = a.first_hits ? hits.data() : nullptr;
    wire::Tile tile{a.frame, a.commit, uint32_t(y0), uint32_t(y0), {}, 0, 0.0, {}, {}, {}, 0.0};
    const Timer tile_timer;
    const double slowdown = frame_slowdown(options_, a.frame);
    // A slowed-down tracer keeps the unit loop: its emulated slowness is spread over units, as
    // a slower machine's would be, and it reacts to a truncation at the next unit.
    const Status s = backend_.times_units() && slowdown <= 1.0
                         ? render_tile_at_once(a, job, y0, y1, rgb, tile)
                         : render_tile_by_units(a, job, y0, y1, slowdown, rgb, tile);
    if (!s) return s;
    if (tile.y1 == uint32_t(y0)) return {};  // nothing of it is wanted any more
    rgb.resize(std::size_t(tile.y1 - tile.y0) * a.width * 3);
    tile.raw_bytes = uint32_t(rgb.size() * sizeof(float));
    if (a.first_hits) {
        hits.resize(std::size_t(tile.y1 - tile.y0) * a.width);
        for (FirstHit& h : hits) {
            if (!h.hit()) continue;
            if (h.instance >= deformed_.size() || !deformed_[h.instance]) {
                h.primitive = FirstHit::kNone;  // zeros that compress away: see mark_deformed
                h.u = h.v = 0.0f;
            }
            h.instance =
                scene_.instances[h.instance].id;  // the commit's, which the coordinator knows
        }
    }
    tile.render_ms = tile_timer.milliseconds();
    tile.update_ms = std::exchange(update_ms_, 0.0);
    // Compressed and sent beside the next tile's render (tile_sender.h).
    sender_.submit({std::move(tile), std::move(rgb), std::move(hits)});
    return {};
}

// One call per unit, each timed; stops between units when the rows went elsewhere (tile.y1
// ends there) or the frame closed (nothing is sent).
Status FrameWorker::render_tile_by_units(const wire::Assignment& a, RenderJob& job, int y0, int y1,
                                         double slowdown, std::vector<float>& rgb,
                                         wire::Tile& tile) {
    for (int y = y0; y < y1; y += kRowsPerWorkUnit) {
        if (control_.newest_commit() > a.commit) {  // the frame closed meanwhile
            tile.y1 = uint32_t(y0);
            return {};
        }
        if (control_.truncated(a, uint32_t(y))) return {};  // send what is done, not the rest
        job.y0 = y;
        job.y1 = std::min(y1, y + kRowsPerWorkUnit);
        FirstHit* hits = job.first_hits;
        if (hits) job.first_hits += std::size_t(y - y0) * a.width;
        const Timer unit;
        auto stats = backend_.render_rows(job, rgb.data() + std::size_t(y - y0) * a.width * 3);
        job.first_hits = hits;
        if (!stats) return stats.error();
        const double unit_s = unit.seconds();
        if (slowdown > 1.0)  // an X times slower machine, unit by unit
            std::this_thread::sleep_for(std::chrono::duration<double>((slowdown - 1.0) * unit_s));
        tile.unit_cost_us.push_back(uint32_t(unit_s * 1e6));
        tile.unit_rays.push_back(stats->counters.rays);
        tile.y1 = uint32_t(job.y1);
    }
    return {};
}

// The whole tile in one parallel call (RenderBackend::times_units): the threads meet once per
// tile instead of once per unit. Units the stop check left out, and any after them, are not
// sent; tile.y1 ends at the first of them.
Status FrameWorker::render_tile_at_once(const wire::Assignment& a, RenderJob& job, int y0, int y1,
                                        std::vector<float>& rgb, wire::Tile& tile) {
    job.y0 = y0;
    job.y1 = y1;
    job.stop = [&](int unit_y0) {
        return control_.newest_commit() > a.commit || control_.truncated(a, uint32_t(unit_y0));
    };
    auto stats = backend_.render_rows(job, rgb.data());
    job.stop = nullptr;
    if (!stats) return stats.error();
    if (control_.newest_commit() > a.commit) return {};  // the frame closed: send nothing
    int end = y0;
    for (const UnitStats& u : stats->units) {
        if (!u.rendered || end >= y1) break;
        tile.unit_cost_us.push_back(uint32_t(u.seconds * 1e6));
        tile.unit_rays.push_back(u.rays);
        end = std::min(y1, end + kRowsPerWorkUnit);
    }
    tile.y1 = uint32_t(end);
    return {};
}

}  // namespace pathfarm::tracer
