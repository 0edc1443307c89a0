// Turns frame N's ChangeSet into commit N (DESIGN.md, "The frame" step 3): only what changed.
#pragma once

#include "common/commit/commit.h"
#include "coordinator/scene_graph/change_set.h"

namespace pathfarm::coord {

// Ops are ordered so every reference is valid when applied: images, textures and materials
// before the meshes that use them, meshes before instances, removals of users before removals
// of what they use. An empty ChangeSet gives an op-less commit (frame and base only).
Commit build_commit(const SceneState& state, const ChangeSet& changes, uint64_t frame,
                    uint64_t base_commit);

}  // namespace pathfarm::coord
