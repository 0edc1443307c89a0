// EmbreeScene: an Embree 3 device and scene built from a SceneModel (RAII), answering the
// integrator's Intersector queries. Meshes used by one instance are baked into the top level
// in world space; meshes used several times become Embree instances of a shared child scene.
#pragma once

#include <memory>

#include "common/base/result.h"
#include "common/render/intersector.h"
#include "common/scene/scene_model.h"

namespace pathfarm::tracer {

class EmbreeScene final : public Intersector {
public:
    // threads = 0 lets Embree use every hardware thread for builds.
    static Result<std::unique_ptr<EmbreeScene>> build(const SceneModel& scene, int threads);
    ~EmbreeScene() override;
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    bool intersect(const Ray& ray, Hit& hit) const override;
    bool occluded(const Ray& ray) const override;

    struct Impl;

private:
    explicit EmbreeScene(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace pathfarm::tracer
