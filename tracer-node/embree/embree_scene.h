// EmbreeScene: an Embree 3 device and a two-level scene built from a SceneModel (RAII),
// answering the integrator's Intersector queries, and updated by what changed instead of built
// anew. Meshes placed once are baked into one scene with one BVH (what a flat scene traces as
// fast as); meshes placed several times, and dynamic instances (Instance::dynamic: the
// coordinator saw them move or deform), have a scene of their own in object space, built at
// high quality, instanced. A camera move within its recentring cell (scene_model.h) costs
// nothing; a moved instanced mesh a top-level commit (with up to 4 000 baked triangles these
// share the top level, so it rebuilds them too; above that the baked scene stands apart and
// every query traverses it, then the top level); a deformed instanced mesh a build of that
// mesh; a moved or deformed baked mesh a build of the baked BVH. What a
// tracer renders never depends on its history: every update gives the bits a fresh build
// gives (IncrementalUpdate.* tests).
// Measured with one scene per mesh instead: 1.4-1.5x the time per ray on Sponza and
// Conference, whose meshes' boxes overlap (docs/performance.md).
#pragma once

#include <memory>

#include "common/base/result.h"
#include "common/render/intersector.h"
#include "common/scene/scene_model.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::tracer {

// What an update did, for logs, benchmarks and tests.
struct EmbreeUpdate {
    int instances_placed = 0;    // instances of shared meshes moved (a top-level commit)
    int instances_rebaked = 0;   // instances of meshes placed once moved (their triangles)
    int meshes_rebaked = 0;      // meshes placed once deformed
    int meshes_rebuilt = 0;      // shared meshes deformed (their scene built again)
    bool baked_rebuilt = false;  // the baked triangles' BVH was built again
};

class EmbreeScene final : public Intersector {
public:
    // threads = 0 lets Embree use every hardware thread for builds.
    static Result<std::unique_ptr<EmbreeScene>> build(const SceneModel& scene, int threads);
    ~EmbreeScene() override;
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // Brings the scene to `scene`, which differs from the last one by `changes` (not
    // structural: the caller builds anew for those). Hits refer to `scene` from now on, so it
    // must outlive its use, as for build.
    Result<EmbreeUpdate> update(const SceneModel& scene, const SceneChanges& changes);

    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;
    // One 8-ray packet with Embree's coherent traversal, where the device has it natively.
    void intersect_coherent(const Ray* rays, int count, Hit* hits, bool* found) const override;

    // The baked triangles have a scene apart from the top level (queries traverse both).
    bool baked_apart() const;

    struct Impl;

private:
    explicit EmbreeScene(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace pathfarm::tracer
