// Generated tangents follow glTF's normal-map convention (audit after the tilted-light bias):
// +Y of a normal map is up in the image, towards decreasing v (v = 0 is the image's top row),
// and the bitangent is cross(normal, tangent.xyz) * tangent.w. They used to point the other
// way, so every normal map without a TANGENT attribute was lit upside down (the Khronos
// NormalTangentTest: docs/rendering.md, "Audit").
#include <gtest/gtest.h>

#include "common/scene/load/procedural_mesh.h"
#include "common/scene/mesh.h"

namespace pathfarm {
namespace {

Vec3 bitangent(const Mesh& m, std::size_t i) {
    return glm::cross(m.normals[i], Vec3(m.tangents[i])) * m.tangents[i].w;
}

// A quad facing +z with the image upright on it: u grows along +x, v grows downwards (-y).
Mesh upright_quad(bool mirrored_u) {
    Mesh m;
    m.positions = {{-1, 1, 0}, {1, 1, 0}, {1, -1, 0}, {-1, -1, 0}};
    m.normals.assign(4, Vec3(0, 0, 1));
    const float u0 = mirrored_u ? 1.0f : 0.0f, u1 = 1.0f - u0;
    m.uvs = {{u0, 0.0f}, {u1, 0.0f}, {u1, 1.0f}, {u0, 1.0f}};
    m.indices = {0, 3, 2, 0, 2, 1};
    return m;
}

TEST(Tangents, BitangentPointsUpTheImage) {
    for (const bool mirrored : {false, true}) {
        Mesh m = upright_quad(mirrored);
        compute_tangents(m);
        ASSERT_EQ(m.tangents.size(), 4u);
        for (std::size_t i = 0; i < 4; ++i) {
            EXPECT_NEAR(m.tangents[i].x, mirrored ? -1.0f : 1.0f, 1e-5f) << i;  // along +u
            EXPECT_NEAR(bitangent(m, i).y, 1.0f, 1e-5f) << "mirrored " << mirrored << " " << i;
        }
    }
}

TEST(Tangents, AgreeWithTheSphereAnalyticFrame) {
    // make_sphere writes its tangents from the parametrisation (u = longitude, v from the top).
    const Mesh sphere = make_sphere(1.0f, 12, 24, 0);
    Mesh generated = sphere;
    generated.tangents.clear();
    compute_tangents(generated);
    int compared = 0;
    for (std::size_t i = 0; i < sphere.positions.size(); ++i) {
        if (std::abs(sphere.normals[i].y) > 0.95f) continue;  // poles: degenerate UVs
        EXPECT_GT(glm::dot(Vec3(generated.tangents[i]), Vec3(sphere.tangents[i])), 0.95f) << i;
        EXPECT_GT(glm::dot(bitangent(generated, i), bitangent(sphere, i)), 0.95f) << i;
        ++compared;
    }
    EXPECT_GT(compared, 200);
}

}  // namespace
}  // namespace pathfarm
