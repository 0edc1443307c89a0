// Quads, cubes, spheres and cylinders.
#include "common/scene/load/procedural_mesh.h"

#include <utility>

namespace pathfarm {

Mesh make_quad(const Vec3& c, const Vec3& u, const Vec3& v, int material) {
    Mesh m;
    m.name = "quad";
    m.material = material;
    m.positions = {c - u - v, c + u - v, c + u + v, c - u + v};
    const Vec3 n = glm::normalize(glm::cross(u, v));
    m.normals.assign(4, n);
    m.uvs = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}};
    m.tangents.assign(4, Vec4(glm::normalize(u), 1.0f));
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

void append_mesh(Mesh& a, const Mesh& b) {
    const auto base = uint32_t(a.positions.size());
    a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
    a.normals.insert(a.normals.end(), b.normals.begin(), b.normals.end());
    a.uvs.insert(a.uvs.end(), b.uvs.begin(), b.uvs.end());
    a.tangents.insert(a.tangents.end(), b.tangents.begin(), b.tangents.end());
    for (uint32_t i : b.indices)
        a.indices.push_back(base + i);
}

Mesh make_unit_cube(int material) {
    Mesh m;
    m.name = "cube";
    m.material = material;
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a) {
        const Vec3 n = axes[a];
        const Vec3 u = axes[(a + 1) % 3];
        const Vec3 v = axes[(a + 2) % 3];
        append_mesh(m, make_quad(0.5f * n, 0.5f * u, 0.5f * v, material));
        append_mesh(m, make_quad(-0.5f * n, 0.5f * v, 0.5f * u, material));
    }
    m.normals.clear();  // flat shading
    return m;
}

Mesh make_sphere(float radius, int rings, int segments, int material) {
    Mesh m;
    m.name = "sphere";
    m.material = material;
    for (int r = 0; r <= rings; ++r) {
        const float theta = kPi * float(r) / float(rings);
        for (int s = 0; s <= segments; ++s) {
            const float phi = 2.0f * kPi * float(s) / float(segments);
            const Vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                         -std::sin(theta) * std::sin(phi));
            m.positions.push_back(radius * n);
            m.normals.push_back(n);
            m.uvs.emplace_back(float(s) / float(segments), float(r) / float(rings));
            m.tangents.emplace_back(-std::sin(phi), 0.0f, -std::cos(phi), 1.0f);
        }
    }
    const int stride = segments + 1;
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = r * stride + s, b = a + 1, c = a + stride, d = c + 1;
            if (r != 0) m.indices.insert(m.indices.end(), {a, c, b});
            if (r != rings - 1) m.indices.insert(m.indices.end(), {b, c, d});
        }
    return m;
}

Mesh turned_inside_out(Mesh m) {
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3)
        std::swap(m.indices[i + 1], m.indices[i + 2]);
    for (Vec3& n : m.normals)
        n = -n;
    return m;
}

Mesh make_cylinder(float radius, float height, int segments, int material) {
    Mesh m;
    m.name = "cylinder";
    m.material = material;
    for (int s = 0; s <= segments; ++s) {
        const float phi = 2.0f * kPi * float(s) / float(segments);
        const Vec3 n(std::cos(phi), 0.0f, -std::sin(phi));
        for (float y : {0.0f, height}) {
            m.positions.push_back(radius * n + Vec3(0.0f, y, 0.0f));
            m.normals.push_back(n);
            m.uvs.emplace_back(float(s) / float(segments), y > 0.0f ? 0.0f : 1.0f);
            m.tangents.emplace_back(-n.z, 0.0f, n.x, 1.0f);
        }
    }
    for (int s = 0; s < segments; ++s) {
        const uint32_t a = 2 * s, b = a + 1, c = a + 2, d = a + 3;
        m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
    }
    // Caps: fans around a centre vertex, with flat normals.
    for (float y : {0.0f, height}) {
        const Vec3 n(0.0f, y > 0.0f ? 1.0f : -1.0f, 0.0f);
        const auto centre = uint32_t(m.positions.size());
        m.positions.emplace_back(0.0f, y, 0.0f);
        m.normals.push_back(n);
        m.uvs.emplace_back(0.5f, 0.5f);
        m.tangents.emplace_back(1.0f, 0.0f, 0.0f, 1.0f);
        for (int s = 0; s <= segments; ++s) {
            const float phi = 2.0f * kPi * float(s) / float(segments);
            m.positions.emplace_back(radius * std::cos(phi), y, -radius * std::sin(phi));
            m.normals.push_back(n);
            m.uvs.emplace_back(0.5f + 0.5f * std::cos(phi), 0.5f + 0.5f * std::sin(phi));
            m.tangents.emplace_back(1.0f, 0.0f, 0.0f, 1.0f);
        }
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = centre + 1 + s, b = a + 1;
            if (y > 0.0f)
                m.indices.insert(m.indices.end(), {centre, a, b});
            else
                m.indices.insert(m.indices.end(), {centre, b, a});
        }
    }
    return m;
}

}  // namespace pathfarm
