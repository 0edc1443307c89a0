// Closed surfaces among world triangles: vertices welded by exact position, triangles joined
// through the edges they share, and the components in which every edge joins exactly two
// triangles. What SealedEmitters builds its enclosures from.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "common/math/types.h"

namespace pathfarm {

// A welded vertex: the bits of an exact world position (+0 and -0 are one position).
struct WeldKey {
    uint32_t x, y, z;
    bool operator==(const WeldKey&) const = default;
};
struct WeldKeyHash {
    std::size_t operator()(const WeldKey& k) const {
        return (std::size_t(k.x) * 0x9e3779b97f4a7c15ULL) ^
               (std::size_t(k.y) * 0xc2b2ae3d27d4eb4fULL) ^
               (std::size_t(k.z) * 0x165667b19e3779f9ULL);
    }
};
WeldKey weld_key(const Vec3& p);

struct Welding {
    std::unordered_map<WeldKey, uint32_t, WeldKeyHash> ids;  // position -> vertex id
    std::vector<WeldKey> keys;         // by vertex id, ids in order of first use
    std::vector<uint32_t> corner_ids;  // three per triangle
};
// Welds `tris` (three world points per triangle).
Welding weld(const std::vector<Vec3>& tris);

// The closed components of the welded triangles, each as its triangles' indices in increasing
// order, components in order of their first triangle. A triangle welded to a line or a point
// (degenerate) belongs to none: it neither closes nor opens a surface.
std::vector<std::vector<uint32_t>> closed_components(const Welding& welding);

}  // namespace pathfarm
