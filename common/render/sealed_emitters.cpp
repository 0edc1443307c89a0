// Closed-surface detection (closed_surfaces.h) over the occluders' world triangles, and
// inside/outside by ray parity (in double, retried in other directions when a ray grazes an
// edge). What is kept from one scene state to the next: sealed_emitters_adopt.cpp.
#include "common/render/sealed_emitters.h"

#include <algorithm>

#include "common/math/transform.h"

namespace pathfarm {
namespace {

// Ray-triangle crossing in double. Returns 1 for a clean crossing at t > 0, 0 for a miss, -1
// when the ray passes within rounding of an edge or vertex or starts on the triangle.
int crossing(const glm::dvec3& o, const glm::dvec3& d, const Vec3& a, const Vec3& b,
             const Vec3& c) {
    const glm::dvec3 p0(a), e1 = glm::dvec3(b) - p0, e2 = glm::dvec3(c) - p0;
    const glm::dvec3 pv = glm::cross(d, e2);
    const double det = glm::dot(e1, pv);
    const double scale = glm::length(e1) * glm::length(e2);
    if (std::abs(det) <= 1e-12 * scale) return 0;  // parallel: the plane is not crossed
    const glm::dvec3 tv = o - p0;
    const double u = glm::dot(tv, pv) / det;
    const glm::dvec3 qv = glm::cross(tv, e1);
    const double v = glm::dot(d, qv) / det;
    const double t = glm::dot(e2, qv) / det;
    constexpr double kEps = 1e-9;
    if (u < -kEps || v < -kEps || u + v > 1.0 + kEps) return 0;
    if (u < kEps || v < kEps || u + v > 1.0 - kEps || std::abs(t) < 1e-9) return -1;
    return t > 0.0 ? 1 : 0;
}

}  // namespace

bool SealedEmitters::occludes(const Material& m) {
    return !(m.transmission_factor > 0.0f) && !m.is_emissive() && !m.alpha_tested();
}

const Material& SealedEmitters::material_of(const SceneModel& scene, std::size_t i) const {
    const Mesh& mesh = scene.meshes[std::size_t(scene.instances[i].mesh)];
    return scene.materials[std::size_t(std::max(mesh.material, 0))];
}

SealedEmitters::Side SealedEmitters::side_of(const Enclosure& e, const Vec3& p) {
    if (!is_finite(p)) return Side::unknown;
    if (p.x < e.bounds.lower.x || p.y < e.bounds.lower.y || p.z < e.bounds.lower.z ||
        p.x > e.bounds.upper.x || p.y > e.bounds.upper.y || p.z > e.bounds.upper.z)
        return Side::outside;
    static const glm::dvec3 kDirections[] = {
        {0.5773, 0.5774, 0.5773}, {-0.3122, 0.8915, -0.3281}, {0.7071, -0.1234, -0.6963}};
    for (const glm::dvec3& dir : kDirections) {
        const glm::dvec3 d = glm::normalize(dir);
        int count = 0;
        bool clean = true;
        for (std::size_t t = 0; t + 2 < e.triangles.size() && clean; t += 3) {
            const int c =
                crossing(glm::dvec3(p), d, e.triangles[t], e.triangles[t + 1], e.triangles[t + 2]);
            if (c < 0) clean = false;
            count += c > 0;
        }
        if (clean) return count % 2 == 1 ? Side::inside : Side::outside;
    }
    return Side::unknown;
}

SealedEmitters::SealedEmitters(const SceneModel& scene)
    : instance_count_(scene.instances.size()), isolated_(scene.instances.size(), false) {
    layout_hash_ = layout_hash(scene);
    position_hashes_ = position_hashes(scene);
    for (const Instance& inst : scene.instances) {
        linear_.push_back(Mat3(inst.transform));
        translation_.push_back(glm::dvec3(Vec3(inst.transform[3])));
    }
    // The opaque occluders' world triangles, the instance of each; none past kMaxTriangles.
    std::vector<Vec3> tris;
    std::vector<uint32_t> instance_of;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        const Mesh& mesh = scene.meshes[std::size_t(inst.mesh)];
        if (!occludes(material_of(scene, i))) continue;
        if (tris.size() / 3 + mesh.triangle_count() > kMaxTriangles) {
            skipped_ = true;
            return;
        }
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
            for (int k = 0; k < 3; ++k)
                tris.push_back(
                    transform_point(inst.transform, mesh.positions[mesh.indices[3 * t + k]]));
            instance_of.push_back(i);
        }
    }
    if (tris.empty()) return;
    Welding welding = weld(tris);
    const auto components = closed_components(welding);
    note_owners(std::move(welding), instance_of);
    add_enclosures(scene, tris, instance_of, components);
}

void SealedEmitters::note_owners(Welding welding, const std::vector<uint32_t>& instance_of) {
    constexpr uint32_t kNone = kShared - 1;
    std::vector<uint32_t> owner(welding.keys.size(), kNone);
    for (std::size_t c = 0; c < welding.corner_ids.size(); ++c) {
        uint32_t& o = owner[welding.corner_ids[c]];
        const uint32_t i = instance_of[c / 3];
        o = o == kNone || o == i ? i : kShared;
    }
    for (uint32_t i : instance_of)
        isolated_[i] = true;
    for (std::size_t c = 0; c < welding.corner_ids.size(); ++c)
        if (owner[welding.corner_ids[c]] == kShared) isolated_[instance_of[c / 3]] = false;
    // The welding's own map becomes the owners' (no second pass of hashing).
    for (auto& [key, id] : welding.ids)
        id = owner[id];
    vertex_owner_ = std::move(welding.ids);
}

void SealedEmitters::add_enclosures(const SceneModel& scene, const std::vector<Vec3>& tris,
                                    const std::vector<uint32_t>& instance_of,
                                    const std::vector<std::vector<uint32_t>>& components) {
    for (const std::vector<uint32_t>& component : components) {
        Enclosure& e = enclosures_.emplace_back();
        e.owner = instance_of[component.front()];
        for (uint32_t t : component) {
            if (instance_of[t] != e.owner) e.owner = kShared;
            for (int k = 0; k < 3; ++k) {
                e.triangles.push_back(tris[3 * t + k]);
                e.bounds.extend(tris[3 * t + k]);
            }
        }
        for (uint32_t i = 0; i < scene.instances.size(); ++i) {
            const Mesh& mesh = scene.meshes[std::size_t(scene.instances[i].mesh)];
            if (material_of(scene, i).is_emissive() && mesh.triangle_count() > 0)
                e.emitters.emplace_back(i, emitter_side(e, scene.instances[i], mesh));
        }
    }
}

// An emissive instance is inside when every vertex, nudged towards its triangle's centre and
// off its front face (panels are often flush with a wall), is inside.
SealedEmitters::Side SealedEmitters::emitter_side(const Enclosure& e, const Instance& inst,
                                                  const Mesh& mesh) const {
    // Bound the parity tests' cost; an emitter left unknown is never culled.
    if (double(mesh.triangle_count()) * 3.0 * double(e.triangles.size() / 3) > 5e7)
        return Side::unknown;
    Side side = Side::unknown;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        Vec3 p[3];
        for (int k = 0; k < 3; ++k)
            p[k] = transform_point(inst.transform, mesh.positions[mesh.indices[3 * t + k]]);
        const Vec3 centre = (p[0] + p[1] + p[2]) / 3.0f;
        const Vec3 normal = glm::cross(p[1] - p[0], p[2] - p[0]);
        const float len = glm::length(normal);
        const float size = std::max({glm::length(p[1] - p[0]), glm::length(p[2] - p[0]), 1e-6f});
        const Vec3 off = len > 0.0f ? normal / len * (1e-3f * size) : Vec3(0.0f);
        Side tri_side = Side::unknown;
        for (int k = 0; k < 3; ++k) {
            const Side s = side_of(e, glm::mix(p[k], centre, 0.01f) + off);
            tri_side = k == 0 ? s : (s == tri_side ? s : Side::unknown);
        }
        side = t == 0 ? tri_side : (tri_side == side ? side : Side::unknown);
        if (side == Side::unknown) break;
    }
    return side;
}

std::vector<bool> SealedEmitters::culled(const Vec3& viewer_now) const {
    std::vector<bool> out(instance_count_, false);
    const Vec3 viewer(glm::dvec3(viewer_now) - shift_);  // in the analysed scene's coordinates
    for (const Enclosure& e : enclosures_) {
        const Side v = side_of(e, viewer);
        if (v == Side::unknown) continue;
        for (const auto& [instance, side] : e.emitters)
            if (side != Side::unknown && side != v) out[instance] = true;
    }
    return out;
}

void LightCulling::set_scene(const SceneModel& scene) {
    if (!sealed_ || !sealed_->adopt(scene)) sealed_ = std::make_unique<SealedEmitters>(scene);
    fresh_ = true;
}

bool LightCulling::update(const Vec3& eye, bool enabled) {
    if (!fresh_ && enabled == enabled_ && eye == eye_) return false;  // per work unit: no work
    const bool was_fresh = fresh_;
    fresh_ = false;
    enabled_ = enabled;
    eye_ = eye;
    std::vector<bool> excluded;
    if (enabled && sealed_ && sealed_->enclosure_count() > 0) excluded = sealed_->culled(eye);
    if (!was_fresh && excluded == excluded_) return false;
    excluded_ = std::move(excluded);
    return true;
}

}  // namespace pathfarm
