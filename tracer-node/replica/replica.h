// The tracer's replica of the scene (DESIGN.md, "Replica equality"): applies commits as they
// arrive, remembers what they changed, and hands the backend the scene with that change set
// (DESIGN.md, "The frame" step 5), so a backend can update instead of rebuild.
#pragma once

#include <map>
#include <memory>
#include <set>
#include <vector>

#include "common/base/result.h"
#include "common/commit/commit.h"
#include "common/commit/commit_codec.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::tracer {

class Replica {
public:
    // Bulk chunks arrive before the Commit message of the same frame.
    void add_chunk(uint64_t frame, std::shared_ptr<const ParsedChunk> chunk);
    // Decodes a commit with its buffered chunks and applies it. On error the replica is
    // unchanged and the caller should resynchronise (reconnect for a snapshot).
    Status apply(const ParsedCommit& commit, uint64_t frame);
    // Applies an already decoded commit (the parsing done elsewhere, as in tests).
    Status apply(const Commit& commit);

    uint64_t commit() const { return state_.commit; }
    bool initialised() const { return state_.initialised; }
    const ReplicaState& state() const { return state_; }
    // True when commits changed the scene since the last update_scene().
    bool scene_changed() const { return !pending_.empty(); }
    // Brings `scene` (what the last call left there; anything the first time) to the dense form
    // of the replica's state (to_scene_model) and returns the changes since that call, as
    // indices; everything the first time. Only what the commits named is copied
    // (patch_scene_model): a camera move in a textured scene copies no texels.
    SceneChanges update_scene(SceneModel& scene);

private:
    // What changed, by object id, until update_scene turns ids into indices.
    struct PendingChanges {
        bool structure = false, camera = false, settings = false, environment = false;
        bool lights = false;
        std::set<uint32_t> instances, meshes, materials, textures, images;
        bool empty() const;
        static PendingChanges everything() {
            return {true, true, true, true, true, {}, {}, {}, {}, {}};
        }
    };
    void note(const CommitOp& op);

    ReplicaState state_;
    std::map<uint64_t, std::vector<std::shared_ptr<const ParsedChunk>>> chunks_;  // by frame
    PendingChanges pending_ = PendingChanges::everything();  // the first scene is all new
};

}  // namespace pathfarm::tracer
