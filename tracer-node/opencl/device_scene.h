// The scene as the OpenCL kernels read it: flat arrays of the structs in device_types.h,
// packed on the host from a SceneModel and the coordinator's mesh BVHs. Packing is pure CPU
// work (tested without a device); the backend uploads what changed since the last packing.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "common/scene/bvh.h"
#include "common/scene/scene_model.h"
#include "common/scene/texture_mips.h"
#include "tracer-node/backend/render_backend.h"
#include "tracer-node/opencl/device_types.h"

namespace pathfarm::tracer {

// The device arrays on the host, one vector per entry of PF_SCENE_ARRAYS (device_types.h).
struct PackedScene {
#define PF_PACKED_ARRAY(name, type) std::vector<type> name;
    PF_SCENE_ARRAYS(PF_PACKED_ARRAY)
#undef PF_PACKED_ARRAY
    PfSceneGlobals globals{};
    uint32_t features = 0;  // SceneFeature bits the scene needs (scene_features)
    LightSelection light_selection = LightSelection::power;  // in use (auto resolved)
    LightChoice light_choice{};                              // how auto chose, if asked
    std::size_t meshes_with_own_bvh = 0;  // meshes whose BVH the tracer built (none provided)
};

// Mesh BVHs the tracer built itself, kept across packings and rebuilt only when a mesh's
// positions or indices change.
class LocalBvhCache {
public:
    const Bvh& get(std::size_t mesh_index, const Mesh& mesh);

private:
    struct Entry {
        uint64_t content = 0;
        Bvh bvh;
    };
    std::map<std::size_t, Entry> entries_;
};

// Whether nodes/prim_indices form a BVH the kernels can traverse safely over a mesh of
// triangle_count triangles (children in range, left child next, leaves inside prim_indices).
bool is_traversable_bvh(const std::vector<BvhNode>& nodes, const std::vector<uint32_t>& prims,
                        std::size_t triangle_count);

// bvhs is indexed like scene.meshes (may be shorter or empty). With mips, each image's levels
// past 0 follow it in the texel array (PfTexture::levels).
PackedScene pack_scene(const SceneModel& scene, const std::vector<MeshBvhView>& bvhs,
                       LocalBvhCache& cache, const TextureMips* mips = nullptr);

// (Re)fills out.lights, out.light_guide (power's guide table), out.light_nodes (the light tree,
// for LightSelection::tree), out.globals' light fields and the instances' first_light for the
// emitters not flagged in `excluded` (LightSampler's exclusion); out.instances must be packed.
// `topology`: the per-mesh light trees kept from earlier states (the same tree either way).
void pack_lights(const SceneModel& scene, const std::vector<bool>& excluded,
                 LightSelection selection, PackedScene& out,
                 LightTopologyCache* topology = nullptr);

}  // namespace pathfarm::tracer
