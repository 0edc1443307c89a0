// The tracer's replica of the scene (DESIGN.md, "Replica equality"): applies commits received
// as wire messages and hands the backend a SceneModel when the scene changed.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/commit/commit.h"

namespace pathfarm::tracer {

class Replica {
public:
    // Bulk chunks arrive before the Commit message of the same frame.
    void add_chunk(uint64_t frame, std::string chunk_bytes);
    // Decodes and applies a commit with its buffered chunks. On error the replica is unchanged
    // and the caller should resynchronise (reconnect for a snapshot).
    Status apply(const std::string& commit_bytes, uint64_t frame);

    uint64_t commit() const { return state_.commit; }
    bool initialised() const { return state_.initialised; }
    const ReplicaState& state() const { return state_; }
    // True when commits changed the scene since the last take_scene_model().
    bool scene_changed() const { return changed_; }
    SceneModel take_scene_model();

private:
    ReplicaState state_;
    std::map<uint64_t, std::vector<std::string>> chunks_;  // by frame
    bool changed_ = true;
};

}  // namespace pathfarm::tracer
