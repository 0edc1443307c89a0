// The flat BVH node layout (derived scene data) shared by the coordinator's builder, its CPU
// traversal and (later) the OpenCL kernels: plain 32-byte nodes in depth-first order. For an
// interior node the left child is the next node and `first` is the right child; for a leaf `first`
// indexes the primitive index array and `count` (> 0) is the number of primitives.
#pragma once

#include <cstdint>

namespace pathfarm {

struct BvhNode {
    float lower[3];
    uint32_t first;
    float upper[3];
    uint32_t count;  // 0 for interior nodes
};
static_assert(sizeof(BvhNode) == 32, "BvhNode is read by device kernels");

}  // namespace pathfarm
