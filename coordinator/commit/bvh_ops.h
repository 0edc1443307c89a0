// BVH commit ops for replicas that traverse the coordinator's BVH (OpenCL tracers): only the
// node ranges that changed since the previous frame's structure.
#pragma once

#include <vector>

#include "common/commit/commit.h"
#include "coordinator/accel/accel_updater.h"

namespace pathfarm::coord {

// Ops that bring a replica holding `previous` (nullptr: nothing) to `next`. Unchanged meshes
// (the same shared BVH) cost nothing; a refit sends the changed node range; a build or
// rebuild also sends the primitive order; the top level is sent whole when it changed.
std::vector<CommitOp> build_bvh_ops(const AccelSnapshot* previous, const AccelSnapshot& next);

// The snapshot's BVH data in the form replicas hold, for checking them (bvh_hash).
DerivedBvh derived_bvh(const AccelSnapshot& snapshot);

}  // namespace pathfarm::coord
