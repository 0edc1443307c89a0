// Bottom-level BVH over a triangle mesh: binned SAH build, refit, and its SAH cost. The node
// layout is BvhNode (common/scene/bvh_node.h), portable to device kernels.
#pragma once

#include <vector>

#include "common/math/types.h"
#include "common/scene/bvh_node.h"

namespace pathfarm {

struct Bvh {
    std::vector<BvhNode> nodes;          // depth first; nodes[0] is the root
    std::vector<uint32_t> prim_indices;  // leaf ranges index this; values are triangle indices
    Bounds3f bounds() const;
};

inline constexpr int kMaxLeafPrims = 4;
inline constexpr int kSahBins = 16;

// Builds over triangles (three positions indexed by `indices` per triangle). Empty input gives
// an empty BVH. Binned SAH (16 bins on the longest centroid axis), leaves of at most 4.
Bvh build_bvh(const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices);
// Builds over arbitrary primitive boxes (used by the top level over instances).
Bvh build_bvh(const std::vector<Bounds3f>& boxes);

// Recomputes every box bottom-up for moved vertices; the topology stays.
void refit_bvh(Bvh& bvh, const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices);

// Surface-area-heuristic cost relative to the root's area: traversal cost 1 per interior node
// visit, intersection cost 1 per primitive. Refits degrade it; rebuilding restores it.
double sah_cost(const Bvh& bvh);

}  // namespace pathfarm
