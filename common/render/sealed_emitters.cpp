// Closed-surface detection by edge counting over welded world vertices, and inside/outside by
// ray parity (in double, retried in other directions when a ray grazes an edge).
#include "common/render/sealed_emitters.h"

#include <algorithm>
#include <bit>
#include <numeric>
#include <optional>
#include <unordered_map>

#include "common/base/hash.h"
#include "common/math/transform.h"

namespace pathfarm {
namespace {

struct VertexKey {
    uint32_t x, y, z;
    bool operator==(const VertexKey&) const = default;
};
struct VertexKeyHash {
    std::size_t operator()(const VertexKey& k) const {
        return (std::size_t(k.x) * 0x9e3779b97f4a7c15ULL) ^
               (std::size_t(k.y) * 0xc2b2ae3d27d4eb4fULL) ^
               (std::size_t(k.z) * 0x165667b19e3779f9ULL);
    }
};

// +0 and -0 are one position.
VertexKey key_of(const Vec3& p) {
    auto bits = [](float f) { return std::bit_cast<uint32_t>(f == 0.0f ? 0.0f : f); };
    return {bits(p.x), bits(p.y), bits(p.z)};
}

struct UnionFind {
    std::vector<uint32_t> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t find(uint32_t a) {
        while (parent[a] != a)
            a = parent[a] = parent[parent[a]];
        return a;
    }
    void unite(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

bool is_opaque_occluder(const Material& m) {
    // Glass, emitters and cut-out or blended surfaces (alpha) let light through.
    return !(m.transmission_factor > 0.0f) && !m.is_emissive() && !m.alpha_tested();
}

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

uint64_t SealedEmitters::geometry_hash(const SceneModel& scene) {
    uint64_t h = fnv1a64(nullptr, 0);
    auto add = [&h](const void* data, std::size_t size) {
        h = fnv1a64(static_cast<const unsigned char*>(data), size, h);
    };
    for (const Mesh& m : scene.meshes) {
        add(m.positions.data(), m.positions.size() * sizeof(Vec3));
        add(m.indices.data(), m.indices.size() * sizeof(uint32_t));
        add(&m.material, sizeof m.material);
    }
    for (const Material& m : scene.materials) {
        const uint8_t flags = uint8_t(is_opaque_occluder(m)) | uint8_t(m.is_emissive() << 1);
        add(&flags, 1);
    }
    for (const Instance& inst : scene.instances)
        add(&inst.mesh, sizeof inst.mesh);
    return h;
}

bool SealedEmitters::adopt_translated(const SceneModel& scene) {
    if (scene.instances.size() != instance_count_ || geometry_hash(scene) != geometry_hash_)
        return false;
    return translated(scene);
}

bool SealedEmitters::translated(const SceneModel& scene) {
    std::optional<glm::dvec3> delta;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        const Mat4& m = scene.instances[i].transform;
        if (Mat3(m) != linear_[i]) return false;
        const glm::dvec3 d = glm::dvec3(Vec3(m[3])) - translation_[i];
        if (!delta) delta = d;
        // Camera-relative shifts are computed in double and rounded to float per instance.
        const double tolerance = 1e-6 * (1.0 + glm::length(glm::dvec3(Vec3(m[3]))));
        if (glm::length(d - *delta) > tolerance) return false;
    }
    shift_ = delta.value_or(glm::dvec3(0.0));
    return true;
}

bool SealedEmitters::placed_as_analysed(const SceneModel& scene, std::size_t i) const {
    const Mat4& m = scene.instances[i].transform;
    return Mat3(m) == linear_[i] && glm::dvec3(Vec3(m[3])) == translation_[i];
}

bool SealedEmitters::adopt(const SceneModel& scene) {
    if (scene.instances.size() != instance_count_ || geometry_hash(scene) != geometry_hash_)
        return false;
    return translated(scene) || moved_emitters(scene);
}

bool SealedEmitters::adopt_moved_emitters(const SceneModel& scene) {
    if (scene.instances.size() != instance_count_ || geometry_hash(scene) != geometry_hash_)
        return false;
    return moved_emitters(scene);
}

bool SealedEmitters::moved_emitters(const SceneModel& scene) {
    if (shift_ != glm::dvec3(0.0)) return false;
    std::vector<uint32_t> moved, emitters;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        if (placed_as_analysed(scene, i)) continue;
        const Mesh& mesh = scene.meshes[std::size_t(scene.instances[i].mesh)];
        const Material& m = scene.materials[std::size_t(std::max(mesh.material, 0))];
        if (is_opaque_occluder(m)) return false;  // the closed surfaces may have changed
        moved.push_back(i);
        if (m.is_emissive()) emitters.push_back(i);
    }
    for (uint32_t i : moved) {
        linear_[i] = Mat3(scene.instances[i].transform);
        translation_[i] = glm::dvec3(Vec3(scene.instances[i].transform[3]));
    }
    for (Enclosure& e : enclosures_)
        for (auto& [instance, side] : e.emitters)
            if (std::binary_search(emitters.begin(), emitters.end(), instance))
                side = emitter_side(e, scene.instances[instance],
                                    scene.meshes[std::size_t(scene.instances[instance].mesh)]);
    return true;
}

namespace {

// World triangles (three points each) of the opaque occluders; nothing past kMaxTriangles.
std::optional<std::vector<Vec3>> occluder_triangles(const SceneModel& scene) {
    std::vector<Vec3> tris;
    for (const Instance& inst : scene.instances) {
        const Mesh& mesh = scene.meshes[std::size_t(inst.mesh)];
        const Material& m = scene.materials[std::size_t(std::max(mesh.material, 0))];
        if (!is_opaque_occluder(m)) continue;
        if (tris.size() / 3 + mesh.triangle_count() > SealedEmitters::kMaxTriangles)
            return std::nullopt;
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k)
                tris.push_back(
                    transform_point(inst.transform, mesh.positions[mesh.indices[3 * t + k]]));
    }
    return tris;
}

// The welded mesh's connectivity: triangles joined through shared edges, and which of those
// components are closed (every edge used by exactly two triangles).
struct Connectivity {
    UnionFind components;
    std::vector<bool> degenerate;  // welded away: it neither closes nor opens a surface
    std::vector<uint8_t> open;     // by component root
    explicit Connectivity(std::size_t n) : components(n), degenerate(n, false), open(n, 0) {}
};

Connectivity connect(const std::vector<Vec3>& tris) {
    const std::size_t n = tris.size() / 3;
    std::unordered_map<VertexKey, uint32_t, VertexKeyHash> vertex_ids;
    std::vector<uint32_t> ids(tris.size());
    for (std::size_t i = 0; i < tris.size(); ++i)
        ids[i] = vertex_ids.emplace(key_of(tris[i]), uint32_t(vertex_ids.size())).first->second;
    Connectivity c(n);
    // Undirected edge -> (triangles using it, one of them).
    std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> edges;
    for (uint32_t t = 0; t < n; ++t) {
        const uint32_t v[3] = {ids[3 * t], ids[3 * t + 1], ids[3 * t + 2]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
            c.degenerate[t] = true;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = std::min(v[k], v[(k + 1) % 3]), b = std::max(v[k], v[(k + 1) % 3]);
            auto [it, added] = edges.try_emplace((uint64_t(a) << 32) | b, 0u, t);
            ++it->second.first;
            if (!added) c.components.unite(t, it->second.second);
        }
    }
    for (const auto& [edge, use] : edges)
        if (use.first != 2) c.open[c.components.find(use.second)] = 1;
    return c;
}

}  // namespace

SealedEmitters::SealedEmitters(const SceneModel& scene) : instance_count_(scene.instances.size()) {
    geometry_hash_ = geometry_hash(scene);
    for (const Instance& inst : scene.instances) {
        linear_.push_back(Mat3(inst.transform));
        translation_.push_back(glm::dvec3(Vec3(inst.transform[3])));
    }
    const auto tris = occluder_triangles(scene);
    if (!tris || tris->empty()) return;
    find_enclosures(*tris);
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Mesh& mesh = scene.meshes[std::size_t(scene.instances[i].mesh)];
        if (!scene.materials[std::size_t(std::max(mesh.material, 0))].is_emissive() ||
            mesh.triangle_count() == 0)
            continue;
        for (Enclosure& e : enclosures_)
            e.emitters.emplace_back(i, emitter_side(e, scene.instances[i], mesh));
    }
}

void SealedEmitters::find_enclosures(const std::vector<Vec3>& tris) {
    Connectivity c = connect(tris);
    std::unordered_map<uint32_t, std::size_t> enclosure_of_root;
    for (uint32_t t = 0; t < tris.size() / 3; ++t) {
        if (c.degenerate[t]) continue;
        const uint32_t root = c.components.find(t);
        if (c.open[root]) continue;
        auto [it, added] = enclosure_of_root.try_emplace(root, enclosures_.size());
        if (added) enclosures_.emplace_back();
        Enclosure& e = enclosures_[it->second];
        for (int k = 0; k < 3; ++k) {
            e.triangles.push_back(tris[3 * t + k]);
            e.bounds.extend(tris[3 * t + k]);
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
