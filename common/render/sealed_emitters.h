// Emitters in unreachable rooms: an emissive instance that a closed, opaque surface separates
// from the viewer cannot light anything the viewer sees (light cannot cross the surface), so
// next-event estimation should not spend samples on it (DESIGN.md, "skip what a scene doesn't
// need"). The test is conservative: whenever closedness or inside/outside is in doubt, the
// emitter stays.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "common/render/closed_surfaces.h"
#include "common/scene/scene_model.h"

namespace pathfarm {

class SealedEmitters {
public:
    // Above this many opaque triangles the analysis is skipped (no emitter is ever culled):
    // it runs whenever a backend gets a new scene state.
    static constexpr std::size_t kMaxTriangles = 300000;

    // Finds closed surfaces: connected sets of opaque, non-emissive triangles (across instances,
    // vertices welded by exact world position) in which every edge joins exactly two
    // triangles; and which emissive instances lie inside each.
    explicit SealedEmitters(const SceneModel& scene);

    // Per instance: true for an emissive instance separated from `viewer` by a closed surface
    // (inside one the viewer is outside of, or outside one the viewer is inside).
    std::vector<bool> culled(const Vec3& viewer) const;
    std::size_t enclosure_count() const { return enclosures_.size(); }

    // Whether `scene` is the analysed scene moved as a whole by one translation (what
    // camera-relative rendering does to every instance when the camera moves); if so the
    // analysis is kept and culled() takes viewers in the moved scene's coordinates. Costs a
    // pass over the meshes' bytes instead of a new analysis.
    bool adopt_translated(const SceneModel& scene);
    // Whether `scene` is the analysed scene with some instances moved (geometry and materials
    // as they were, no translation adopted), where every moved occluder shares no welded
    // vertex with another instance's occluders, before and after (a rolling ball, a swinging
    // door, a turning ring of lights). If so the closed surfaces of the instances that did not
    // move are kept, the moved occluders' own are found again, and every emitter's side of
    // them; the moved emitters' sides of the others. The result equals a new analysis of
    // `scene`; a fraction of its cost. On false the analysis must be replaced.
    bool adopt_moved_instances(const SceneModel& scene);
    // Either of the two (one pass over the geometry), and also when meshes deformed (their
    // vertices moved, their triangles the same): a deformed mesh's instances count as moved,
    // so a deformed occluder must share no welded vertex with another's either (a skinned
    // figure); its surfaces are welded again from its new vertices.
    bool adopt(const SceneModel& scene);

private:
    enum class Side : uint8_t { inside, outside, unknown };
    static constexpr uint32_t kShared = UINT32_MAX;  // a vertex of several instances' occluders
    struct Enclosure {
        std::vector<Vec3> triangles;  // three world positions per triangle
        Bounds3f bounds;
        std::vector<std::pair<uint32_t, Side>> emitters;  // emissive instance, its side
        uint32_t owner = kShared;  // the instance all its triangles belong to, or kShared
    };
    static Side side_of(const Enclosure& e, const Vec3& p);
    // Glass, emitters and cut-out or blended surfaces (alpha) let light through.
    static bool occludes(const Material& m);
    const Material& material_of(const SceneModel& scene, std::size_t instance) const;
    // Which instance each welded vertex of the occluders belongs to (`instance_of` per
    // triangle), kept in vertex_owner_ and isolated_.
    void note_owners(Welding welding, const std::vector<uint32_t>& instance_of);
    // Enclosures from closed `components` of `tris` (three world points per triangle, the
    // instance of each beside), with every emitter's side of them.
    void add_enclosures(const SceneModel& scene, const std::vector<Vec3>& tris,
                        const std::vector<uint32_t>& instance_of,
                        const std::vector<std::vector<uint32_t>>& components);
    Side emitter_side(const Enclosure& e, const Instance& inst, const Mesh& mesh) const;

    // What the adopt functions compare: everything of the geometry but the vertex positions
    // (triangles, materials, which mesh each instance places), and each mesh's positions.
    static uint64_t layout_hash(const SceneModel& scene);
    static std::vector<uint64_t> position_hashes(const SceneModel& scene);
    bool same_layout(const SceneModel& scene) const;
    bool placed_as_analysed(const SceneModel& scene, std::size_t instance) const;
    // adopt_translated and adopt_moved_instances once the geometry is known to be the same;
    // moved_instances also with the meshes flagged in `deformed` (by mesh index; empty: none).
    bool translated(const SceneModel& scene);
    bool moved_instances(const SceneModel& scene, const std::vector<bool>& deformed);
    // A moved or deformed occluder's vertices and enclosures leave the analysis.
    void remove_occluder(const SceneModel& scene, uint32_t instance, bool deformed);
    // Welds moved occluder `instance` alone where `scene` places it (false if it shares a
    // vertex with another instance) and adds its enclosures.
    bool moved_occluder(const SceneModel& scene, uint32_t instance);

    std::size_t instance_count_ = 0;
    std::vector<Enclosure> enclosures_;
    // Every occluder vertex (as analysed, moved occluders where they are now) -> the instance
    // it belongs to, kShared if several.
    std::unordered_map<WeldKey, uint32_t, WeldKeyHash> vertex_owner_;
    std::vector<bool> isolated_;  // an occluder whose vertices are its own alone
    // A moved occluder's mesh welded in its own space. Placed in the world, vertices it keeps
    // apart may meet (rounding, such as a sphere's poles); its closed components are kept for
    // the last such pattern, which a rigid motion rarely changes.
    struct MeshSurfaces {
        Welding welding;
        std::vector<uint32_t> merged;  // per vertex id: the id it met in the world (or itself)
        std::vector<std::vector<uint32_t>> closed;  // for `merged`
        bool fresh = true;
        std::vector<WeldKey> keys;  // its vertices in vertex_owner_ once it moved
        bool placed = false;        // moved since the analysis (else `keys` is not known)
    };
    MeshSurfaces& surfaces_of(const SceneModel& scene, uint32_t instance);
    // The distinct world vertices of `surfaces` placed by `transform`; `merged` as above.
    static std::vector<WeldKey> place(const MeshSurfaces& surfaces, const Mat4& transform,
                                      std::vector<uint32_t>& merged);
    std::unordered_map<uint32_t, MeshSurfaces> mesh_surfaces_;  // by instance, once moved
    bool skipped_ = false;  // over kMaxTriangles: nothing is ever culled
    // What the adopt functions compare: geometry and materials, the instances' linear parts,
    // and their translations (in double, as the analysed scene had them).
    uint64_t layout_hash_ = 0;
    std::vector<uint64_t> position_hashes_;  // by mesh
    std::vector<Mat3> linear_;
    std::vector<glm::dvec3> translation_;
    glm::dvec3 shift_{0.0};  // added to the analysed scene's coordinates by adopt_translated
};

// What a backend keeps for culling: the analysis of its current scene and the emitters left out
// for the current camera, recomputed only when the camera or the scene changed.
class LightCulling {
public:
    // Adopts the previous analysis when the scene only moved as a whole or only emitters
    // moved (SealedEmitters::adopt), else analyses it.
    void set_scene(const SceneModel& scene);
    // The excluded set for a camera at `eye` (none when !enabled); true when it changed since
    // the last call, i.e. the light sampler must be rebuilt.
    bool update(const Vec3& eye, bool enabled);
    const std::vector<bool>& excluded() const { return excluded_; }
    std::size_t enclosure_count() const { return sealed_ ? sealed_->enclosure_count() : 0; }

private:
    std::unique_ptr<SealedEmitters> sealed_;
    std::vector<bool> excluded_;
    bool fresh_ = true;  // no update() since set_scene()
    bool enabled_ = false;
    Vec3 eye_{0.0f};
};

}  // namespace pathfarm
