// ShadingScene: what the integrator needs beyond the SceneModel, precomputed once per scene
// state: per-instance normal matrices and handedness, the surface at a hit, material lookups.
#pragma once

#include <vector>

#include "common/render/bsdf.h"
#include "common/render/intersector.h"
#include "common/scene/scene_model.h"
#include "common/scene/texture_mips.h"

namespace pathfarm {

// A surface point in world space.
struct SurfacePoint {
    Vec3 p{0.0f};
    Vec3 ng{0.0f, 0.0f, 1.0f};  // unit geometric normal of the front (CCW) face
    Vec3 ns{0.0f, 0.0f, 1.0f};  // unit shading normal (interpolated), on ng's side
    Vec3 tangent{0.0f};         // world-space tangent (zero when the mesh has none)
    float bitangent_sign = 1.0f;
    Vec2 uv{0.0f};
    float uv_density = 0.0f;  // uv area per world area of the triangle (texture level of detail)
    int material = 0;
};

class ShadingScene {
public:
    // With mips, material_point reads coarser texture levels for wide path footprints.
    explicit ShadingScene(const SceneModel& scene, const TextureMips* mips = nullptr);

    const SceneModel& model() const { return scene_; }
    SurfacePoint surface(const Hit& hit) const;
    // World-space vertices of a triangle of an instance.
    void triangle_vertices(uint32_t instance, uint32_t prim, Vec3 p[3]) const;
    // Material parameters at sp, with its shading normal bent by the normal map. `footprint`
    // is the world-space area a path's ray cone covers at sp (0: the camera's hit, level 0).
    MaterialPoint material_point(SurfacePoint& sp, float footprint = 0.0f) const;
    // Radiance emitted at sp towards wo (front face only unless double-sided).
    Rgb emitted(const SurfacePoint& sp, const Vec3& wo) const;
    Rgb absorption_coefficient(int material) const;  // Beer: sigma_a per metre

private:
    // The image a texture reference reads for a footprint (texture_mips.h).
    const Image* texture_level(const TextureRef& ref, const SurfacePoint& sp,
                               float footprint) const;

    const SceneModel& scene_;
    const TextureMips* mips_ = nullptr;
    std::vector<Mat3> normal_matrices_;
    std::vector<float> handedness_;  // sign of each instance transform's determinant
};

}  // namespace pathfarm
