// OBJ pose export: node-index order, one v per accessor vertex, valid 1-based faces, world space.
#include "coordinator/export/obj_export.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "common/scene/load/scene_loader.h"
#include "coordinator/animation/animator.h"
#include "coordinator/animation/skinning.h"
#include "tests/support/test_env.h"

namespace pathfarm::coord {
namespace {

struct ObjCounts {
    std::vector<std::string> objects;
    std::vector<Vec3> vertices;
    std::size_t faces = 0;
    bool faces_valid = true;
};

ObjCounts parse(const std::string& path) {
    ObjCounts c;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "o") {
            std::string name;
            ls >> name;
            c.objects.push_back(name);
        } else if (tag == "v") {
            Vec3 v;
            ls >> v.x >> v.y >> v.z;
            c.vertices.push_back(v);
        } else if (tag == "f") {
            std::size_t a, b, d;
            ls >> a >> b >> d;
            ++c.faces;
            c.faces_valid &= a >= 1 && b >= 1 && d >= 1 && a <= c.vertices.size() &&
                             b <= c.vertices.size() && d <= c.vertices.size();
        }
    }
    return c;
}

TEST(ObjExport, BoxAnimatedNodesInSourceOrderWithAllVertices) {
    PF_REQUIRE_SCENES(scenes);
    auto scene = load_scene(scenes + "/box-animated/BoxAnimated.gltf");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    apply_clip(*scene, 0, 1.0f);
    const SceneModel posed = pose_scene(*scene);
    const std::string out = test::scratch_dir() + "/box.obj";
    ASSERT_TRUE(export_posed_obj(posed, out).ok());
    const ObjCounts c = parse(out);
    std::size_t vertices = 0, triangles = 0;
    std::vector<int> sources;
    for (const Instance& inst : posed.instances) {
        vertices += posed.meshes[inst.mesh].positions.size();
        triangles += posed.meshes[inst.mesh].triangle_count();
    }
    for (const Node& n : posed.nodes)
        if (!n.meshes.empty()) sources.push_back(n.source_index);
    std::sort(sources.begin(), sources.end());
    EXPECT_EQ(c.vertices.size(), vertices);
    EXPECT_EQ(c.faces, triangles);
    EXPECT_TRUE(c.faces_valid);
    ASSERT_EQ(c.objects.size(), sources.size());
}

TEST(ObjExport, SkinnedExportIsWorldSpaceSkinnedPositions) {
    PF_REQUIRE_SCENES(scenes);
    auto scene = load_scene(scenes + "/rigged-simple/RiggedSimple.gltf");
    ASSERT_TRUE(scene.ok());
    apply_clip(*scene, 0, 0.7f);
    const SceneModel posed = pose_scene(*scene);
    const std::string out = test::scratch_dir() + "/rs.obj";
    ASSERT_TRUE(export_posed_obj(posed, out).ok());
    const ObjCounts c = parse(out);
    const Mesh& mesh = posed.meshes[posed.instances[0].mesh];
    ASSERT_EQ(c.vertices.size(), mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        EXPECT_NEAR(glm::distance(c.vertices[v], mesh.positions[v]), 0.0f, 1e-5f);
}

TEST(ObjExport, UnwritablePathIsAnError) {
    SceneModel empty;
    const auto s = export_posed_obj(empty, "/no/such/dir/x.obj");
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("/no/such/dir/x.obj"), std::string::npos);
}

}  // namespace
}  // namespace pathfarm::coord
