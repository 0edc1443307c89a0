// The light tree's fixed part (docs/rendering.md, "Lights"): per emissive mesh, a tree over its
// triangles built once in mesh space, whose subtrees (LightTree::clusters) every state's tree
// keeps and refits in world space under a top level built anew over them. The topology is a
// function of the mesh alone, so every tracer, one that joined late too, builds the same tree
// for the same state, and a moving or turning emitter costs a refit, not a build.
#pragma once

#include <cstdint>
#include <unordered_map>

#include "common/render/light_tree.h"
#include "common/scene/mesh.h"

namespace pathfarm {

// The tree over `mesh`'s triangles in mesh space: area as power, `two_sided` as its material.
LightTree mesh_light_tree(const Mesh& mesh, bool two_sided);

// mesh_light_tree of each mesh, kept while its geometry is unchanged.
class LightTopologyCache {
public:
    const LightTree& mesh_tree(const Mesh& mesh, bool two_sided);
    // Forgets the trees not asked for since the last call (meshes gone or changed).
    void end_state();
    std::size_t builds() const { return builds_; }  // trees built so far

private:
    struct Entry {
        LightTree tree;
        bool used = true;
    };
    std::unordered_map<uint64_t, Entry> trees_;  // by geometry and sidedness
    std::size_t builds_ = 0;
};

}  // namespace pathfarm
