// Derived per-vertex attributes of meshes.
#include "common/scene/mesh.h"

#include "common/math/frame.h"

namespace pathfarm {

void compute_tangents(Mesh& mesh) {
    if (!mesh.has_uvs() || !mesh.has_normals()) return;
    std::vector<Vec3> tan(mesh.positions.size(), Vec3(0.0f));
    std::vector<Vec3> bitan(mesh.positions.size(), Vec3(0.0f));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
        const Vec3 e1 = mesh.positions[i1] - mesh.positions[i0];
        const Vec3 e2 = mesh.positions[i2] - mesh.positions[i0];
        const Vec2 d1 = mesh.uvs[i1] - mesh.uvs[i0];
        const Vec2 d2 = mesh.uvs[i2] - mesh.uvs[i0];
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (std::abs(det) < 1e-20f) continue;
        const float r = 1.0f / det;
        const Vec3 sdir = (e1 * d2.y - e2 * d1.y) * r;
        const Vec3 tdir = (e2 * d1.x - e1 * d2.x) * r;
        for (uint32_t i : {i0, i1, i2}) {
            tan[i] += sdir;
            bitan[i] += tdir;
        }
    }
    mesh.tangents.resize(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const Vec3 n = mesh.normals[i];
        const Frame f = Frame::from_normal_tangent(n, tan[i]);
        // glTF: +Y of a normal map is up in the image, towards decreasing v (v = 0 is the top
        // row), and the bitangent is cross(n, t) * w: w makes it point against dP/dv.
        const float w = glm::dot(glm::cross(n, f.t), bitan[i]) > 0.0f ? -1.0f : 1.0f;
        mesh.tangents[i] = Vec4(f.t, w);
    }
}

void compute_smooth_normals(Mesh& mesh) {
    mesh.normals.assign(mesh.positions.size(), Vec3(0.0f));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
        const Vec3 n = glm::cross(mesh.positions[i1] - mesh.positions[i0],
                                  mesh.positions[i2] - mesh.positions[i0]);
        mesh.normals[i0] += n;
        mesh.normals[i1] += n;
        mesh.normals[i2] += n;
    }
    for (Vec3& n : mesh.normals) {
        const float len = glm::length(n);
        n = len > 0.0f ? n / len : Vec3(0.0f, 0.0f, 1.0f);
    }
}

}  // namespace pathfarm
