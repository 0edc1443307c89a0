// Replica bookkeeping.
#include "tracer-node/replica/replica.h"

#include "common/commit/commit_codec.h"

namespace pathfarm::tracer {

void Replica::add_chunk(uint64_t frame, std::string chunk_bytes) {
    chunks_[frame].push_back(std::move(chunk_bytes));
}

Status Replica::apply(const std::string& commit_bytes, uint64_t frame) {
    auto chunks = std::move(chunks_[frame]);
    chunks_.erase(chunks_.begin(), chunks_.upper_bound(frame));  // older leftovers are stale
    auto commit = decode_commit(commit_bytes, chunks);
    if (!commit) return commit.error();
    if (Status s = apply_commit(state_, *commit); !s) return s;
    if (!commit->ops.empty()) changed_ = true;
    return {};
}

SceneModel Replica::take_scene_model() {
    changed_ = false;
    return to_scene_model(state_.scene);
}

}  // namespace pathfarm::tracer
