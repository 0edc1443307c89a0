// Emitters in unreachable rooms: an emissive instance that a closed, opaque surface separates
// from the viewer cannot light anything the viewer sees (light cannot cross the surface), so
// next-event estimation should not spend samples on it (DESIGN.md, "skip what a scene doesn't
// need"). The test is conservative: whenever closedness or inside/outside is in doubt, the
// emitter stays.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

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
    // Whether `scene` is the analysed scene with only emitters moved (occluders, geometry and
    // materials as they were, no translation adopted); if so the closed surfaces are kept and
    // only the moved emitters' sides are found again (a turning ring of lights: a fraction of
    // a new analysis).
    bool adopt_moved_emitters(const SceneModel& scene);
    // Either of the two (one pass over the geometry).
    bool adopt(const SceneModel& scene);

private:
    enum class Side : uint8_t { inside, outside, unknown };
    struct Enclosure {
        std::vector<Vec3> triangles;  // three world positions per triangle
        Bounds3f bounds;
        std::vector<std::pair<uint32_t, Side>> emitters;  // emissive instance, its side
    };
    static Side side_of(const Enclosure& e, const Vec3& p);
    // The closed surfaces among the occluders' world triangles (three points each).
    void find_enclosures(const std::vector<Vec3>& tris);
    Side emitter_side(const Enclosure& e, const Instance& inst, const Mesh& mesh) const;

    static uint64_t geometry_hash(const SceneModel& scene);
    bool placed_as_analysed(const SceneModel& scene, std::size_t instance) const;
    // adopt_translated and adopt_moved_emitters once the geometry is known to be the same.
    bool translated(const SceneModel& scene);
    bool moved_emitters(const SceneModel& scene);

    std::size_t instance_count_ = 0;
    std::vector<Enclosure> enclosures_;
    // What adopt_translated() compares: geometry and materials, the instances' linear parts,
    // and their translations (in double, as the analysed scene had them).
    uint64_t geometry_hash_ = 0;
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
