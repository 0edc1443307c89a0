// Scene validation and repair.
#include "common/scene/load/validate.h"

#include <spdlog/spdlog.h>

namespace pathfarm {
namespace {

template <typename V>
bool finite_vec(const V& v) {
    for (int i = 0; i < V::length(); ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

Status check_structure(const SceneModel& scene, const Mesh& mesh, std::size_t m,
                       const std::string& source) {
    const std::size_t n = mesh.positions.size();
    if ((!mesh.normals.empty() && mesh.normals.size() != n) ||
        (!mesh.uvs.empty() && mesh.uvs.size() != n) ||
        (!mesh.tangents.empty() && mesh.tangents.size() != n))
        return make_error(ErrorCode::parse_error,
                          "{}: mesh {} \"{}\": attribute counts differ from {} positions", source,
                          m, mesh.name, n);
    if ((!mesh.joints.empty() && (mesh.joints.size() != n || mesh.weights.size() != n)))
        return make_error(ErrorCode::parse_error,
                          "{}: mesh {} \"{}\": JOINTS_0/WEIGHTS_0 counts differ from {} positions",
                          source, m, mesh.name, n);
    for (const MorphTarget& t : mesh.morph_targets)
        if ((!t.positions.empty() && t.positions.size() != n) ||
            (!t.normals.empty() && t.normals.size() != n) ||
            (!t.tangents.empty() && t.tangents.size() != n))
            return make_error(ErrorCode::parse_error,
                              "{}: mesh {} \"{}\": morph target sizes differ from {} positions",
                              source, m, mesh.name, n);
    if (mesh.indices.size() % 3 != 0)
        return make_error(ErrorCode::parse_error,
                          "{}: mesh {} \"{}\": {} indices is not a multiple of 3", source, m,
                          mesh.name, mesh.indices.size());
    for (uint32_t i : mesh.indices)
        if (i >= n)
            return make_error(ErrorCode::parse_error,
                              "{}: mesh {} \"{}\": index {} out of range ({} vertices)", source, m,
                              mesh.name, i, n);
    if (mesh.material < 0 || mesh.material >= int(scene.materials.size()))
        return make_error(ErrorCode::parse_error, "{}: mesh {} \"{}\": material {} out of range",
                          source, m, mesh.name, mesh.material);
    return {};
}

template <typename V>
std::size_t clear_nonfinite(std::vector<V>& values) {
    std::size_t n = 0;
    for (V& v : values)
        if (!finite_vec(v)) {
            v = V(0.0f);
            ++n;
        }
    return n;
}

void repair_mesh(Mesh& mesh, std::size_t m, const std::string& source, RepairReport& report) {
    std::vector<uint32_t> kept;
    kept.reserve(mesh.indices.size());
    std::size_t nonfinite = 0, degenerate = 0;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const Vec3& a = mesh.positions[mesh.indices[t]];
        const Vec3& b = mesh.positions[mesh.indices[t + 1]];
        const Vec3& c = mesh.positions[mesh.indices[t + 2]];
        if (!finite_vec(a) || !finite_vec(b) || !finite_vec(c)) {
            ++nonfinite;
            continue;
        }
        const Vec3 n = glm::cross(b - a, c - a);
        if (!(glm::dot(n, n) > 0.0f) || !finite_vec(n)) {
            ++degenerate;
            continue;
        }
        kept.insert(kept.end(), {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]});
    }
    const std::size_t attrs =
        clear_nonfinite(mesh.normals) + clear_nonfinite(mesh.uvs) + clear_nonfinite(mesh.tangents);
    if (nonfinite + degenerate > 0)
        spdlog::warn(
            "{}: mesh {} \"{}\": dropped {} triangles with NaN/Inf vertices and {} degenerate "
            "triangles",
            source, m, mesh.name, nonfinite, degenerate);
    if (attrs > 0)
        spdlog::warn("{}: mesh {} \"{}\": {} non-finite normals/UVs/tangents replaced by 0", source,
                     m, mesh.name, attrs);
    mesh.indices = std::move(kept);
    report.dropped_nonfinite += nonfinite;
    report.dropped_degenerate += degenerate;
    report.repaired_attributes += attrs;
}

float clamp_or(float v, float lo, float hi, float fallback) {
    return std::isfinite(v) ? std::clamp(v, lo, hi) : fallback;
}

void repair_material(Material& m) {
    for (int c = 0; c < 4; ++c)
        m.base_color_factor[c] = clamp_or(m.base_color_factor[c], 0.0f, 1.0f, 1.0f);
    m.metallic_factor = clamp_or(m.metallic_factor, 0.0f, 1.0f, 0.0f);
    m.roughness_factor = clamp_or(m.roughness_factor, 0.0f, 1.0f, 1.0f);
    m.transmission_factor = clamp_or(m.transmission_factor, 0.0f, 1.0f, 0.0f);
    m.ior = clamp_or(m.ior, 1.0f, 5.0f, 1.5f);
    if (m.ior == 1.0f) m.ior = 1.0001f;  // keep Fresnel well defined
    m.specular_factor = clamp_or(m.specular_factor, 0.0f, 1.0f, 1.0f);
    for (int c = 0; c < 3; ++c) {
        m.emissive_factor[c] = clamp_or(m.emissive_factor[c], 0.0f, 1e6f, 0.0f);
        m.specular_color_factor[c] = clamp_or(m.specular_color_factor[c], 0.0f, 1e3f, 1.0f);
        m.attenuation_color[c] = clamp_or(m.attenuation_color[c], 0.0f, 1.0f, 1.0f);
    }
    m.emissive_strength = clamp_or(m.emissive_strength, 0.0f, 1e6f, 1.0f);
    if (!(m.attenuation_distance > 0.0f)) m.attenuation_distance = kInfinity;
    m.alpha_cutoff = clamp_or(m.alpha_cutoff, 0.0f, 1.0f, 0.5f);
    for (TextureRef* t : {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture,
                          &m.emissive_texture}) {
        const UvTransform& x = t->transform;
        if (!finite_vec(x.offset) || !finite_vec(x.scale) || !std::isfinite(x.rotation))
            t->transform = UvTransform{};  // a NaN transform would make every lookup NaN
    }
}

}  // namespace

Status validate_and_repair(SceneModel& scene, const std::string& source, RepairReport* report) {
    RepairReport local;
    RepairReport& r = report ? *report : local;
    for (Texture& t : scene.textures)
        if (t.image >= int(scene.images.size())) t.image = -1;
    for (Material& m : scene.materials)
        repair_material(m);
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        if (Status s = check_structure(scene, scene.meshes[m], m, source); !s) return s;
        repair_mesh(scene.meshes[m], m, source, r);
    }
    for (const Node& node : scene.nodes) {
        if (node.skin < 0) continue;
        if (node.skin >= int(scene.skins.size()))
            return make_error(ErrorCode::parse_error, "{}: node \"{}\": skin {} out of range",
                              source, node.name, node.skin);
        const std::size_t joints = scene.skins[node.skin].joints.size();
        for (int mi : node.meshes)
            for (const auto& j : scene.meshes[mi].joints)
                if (j.x >= joints || j.y >= joints || j.z >= joints || j.w >= joints)
                    return make_error(ErrorCode::parse_error,
                                      "{}: mesh \"{}\": joint index beyond the skin's {} joints",
                                      source, scene.meshes[mi].name, joints);
    }
    for (const Instance& inst : scene.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(scene.meshes.size()))
            return make_error(ErrorCode::parse_error, "{}: instance of missing mesh {}", source,
                              inst.mesh);
        for (int c = 0; c < 4; ++c)
            if (!finite_vec(inst.transform[c]))
                return make_error(ErrorCode::parse_error, "{}: node {}: non-finite transform",
                                  source, inst.node);
    }
    return {};
}

}  // namespace pathfarm
