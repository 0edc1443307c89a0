// Replica equality (DESIGN.md): random edit sequences through the scene graph, the commit
// builder and the wire codec; after every commit the replica's content hash equals the
// coordinator's. Late joiners start from a snapshot. Commits on the wrong base are refused. A
// tracer's dense model, patched commit by commit, equals the whole conversion of its state.
#include <set>

#include <gtest/gtest.h>

#include "common/commit/commit_codec.h"
#include "common/sampling/rng.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/procedural_mesh.h"
#include "coordinator/commit/commit_builder.h"
#include "coordinator/scene_graph/scene_graph.h"
#include "tests/support/commit_wire.h"
#include "tracer-node/replica/replica.h"

namespace pathfarm::coord {
namespace {

template <typename Set>
uint32_t pick(Pcg32& rng, const Set& ids) {
    auto it = ids.begin();
    std::advance(it, rng.next_u32() % ids.size());
    return it->first;
}

Mat4 random_transform(Pcg32& rng) {
    const Vec3 t(rng.next_float() * 2 - 1, rng.next_float(), rng.next_float() * 2 - 1);
    return glm::translate(Mat4(1.0f), t) * glm::scale(Mat4(1.0f), Vec3(0.1f + rng.next_float()));
}

// Edit `kind` (0-10) with random arguments; 0, 1, 3, 4 and 8 add or remove objects.
void random_edit(SceneGraph& g, Pcg32& rng, std::vector<uint32_t>& nodes, uint32_t kind) {
    const SceneState& s = g.state();
    switch (kind) {
        case 0: {  // add a mesh and an instance of it
            Mesh m = make_sphere(0.1f + rng.next_float(), 3 + rng.next_u32() % 5,
                                 4 + rng.next_u32() % 6, int(pick(rng, s.materials)));
            nodes.push_back(*g.add_node(g.add_mesh(std::move(m)), random_transform(rng)));
            break;
        }
        case 1:
            if (!s.meshes.empty())
                nodes.push_back(*g.add_node(pick(rng, s.meshes), random_transform(rng)));
            break;
        case 2:
            if (!nodes.empty())
                (void)g.set_node_transform(nodes[rng.next_u32() % nodes.size()],
                                           random_transform(rng));
            break;
        case 3:
            if (!nodes.empty()) {
                const std::size_t k = rng.next_u32() % nodes.size();
                (void)g.remove_node(nodes[k]);
                nodes.erase(nodes.begin() + std::ptrdiff_t(k));
            }
            break;
        case 4:
            if (s.meshes.size() > 3) (void)g.remove_mesh(pick(rng, s.meshes));
            break;
        case 5: {
            const uint32_t id = pick(rng, s.materials);
            Material m = s.materials.at(id);
            m.base_color_factor = Vec4(rng.next_float(), rng.next_float(), rng.next_float(), 1.0f);
            m.roughness_factor = rng.next_float();
            m.alpha_mode = AlphaMode(rng.next_u32() % uint32_t(kAlphaModeCount));
            m.alpha_cutoff = rng.next_float();
            m.base_color_texture.transform.offset = Vec2(rng.next_float(), rng.next_float());
            m.base_color_texture.transform.rotation = rng.next_float() * 6.0f;
            m.normal_texture.transform.scale = Vec2(1.0f + rng.next_float(), 2.0f);
            (void)g.set_material(id, std::move(m));
            break;
        }
        case 6:
            (void)g.set_light(pick(rng, s.materials), Rgb(rng.next_float() * 10),
                              1.0f + rng.next_float(), rng.next_u32() % 2);
            break;
        case 7: {
            const uint32_t id = pick(rng, s.meshes);
            const std::size_t n = s.meshes.at(id).positions.size();
            const uint32_t first = rng.next_u32() % uint32_t(n);
            std::vector<Vec3> p(1 + rng.next_u32() % uint32_t(n - first));
            for (Vec3& v : p)
                v = Vec3(rng.next_float(), rng.next_float(), rng.next_float());
            (void)g.edit_vertices(id, first, p);
            break;
        }
        case 8: {
            Image img{"noise", 4, 4, std::vector<uint8_t>(64)};
            for (uint8_t& b : img.rgba)
                b = uint8_t(rng.next_u32());
            const uint32_t image = g.add_image(std::move(img));
            const uint32_t tex = g.add_texture(Texture{int(image), Sampler{}});
            const uint32_t mat_id = pick(rng, s.materials);
            Material m = s.materials.at(mat_id);
            m.base_color_texture.texture = int(tex);
            (void)g.set_material(mat_id, std::move(m));
            break;
        }
        case 9: {
            Camera c;
            c.camera_to_world = random_transform(rng);
            c.yfov_radians = 0.3f + rng.next_float();
            g.set_camera(s.cameras.empty() || rng.next_u32() % 3 == 0
                             ? std::nullopt
                             : std::optional(pick(rng, s.cameras)),
                         c, rng.next_u32() % 2);
            break;
        }
        default: {
            Environment e = s.environment;
            e.sun_direction = glm::normalize(Vec3(rng.next_float(), 1.0f, rng.next_float()));
            g.set_environment(e);
            RenderSettings r = s.settings;
            r.seed = rng.next_u32();
            g.set_settings(r);
        }
    }
}

TEST(ReplicaEquality, ThousandRandomEditSequences) {
    SceneGraph graph(make_cornell_box());
    ReplicaState replica;
    ASSERT_TRUE(apply_commit(replica, test::through_wire(make_snapshot(graph.state(), 0))).ok());
    ASSERT_EQ(content_hash(replica.scene), content_hash(graph.state()));
    Pcg32 rng(2024);
    std::vector<uint32_t> nodes;
    std::set<uint64_t> distinct;
    for (uint64_t frame = 1; frame <= 1000; ++frame) {
        const int edits = 1 + int(rng.next_u32() % 6);
        for (int e = 0; e < edits; ++e)
            random_edit(graph, rng, nodes, rng.next_u32() % 11);
        graph.advance(double(frame) / 30.0);
        const Commit commit = build_commit(graph.state(), graph.take_changes(), frame, frame - 1);
        const Status applied = apply_commit(replica, test::through_wire(commit));
        ASSERT_TRUE(applied.ok()) << "frame " << frame << ": " << applied.error().message;
        ASSERT_EQ(content_hash(replica.scene), content_hash(graph.state())) << "frame " << frame;
        distinct.insert(content_hash(replica.scene));
        if (frame % 250 == 0) {  // a tracer joining late: snapshot, then commits
            ReplicaState late;
            ASSERT_TRUE(
                apply_commit(late, test::through_wire(make_snapshot(graph.state(), frame))).ok());
            EXPECT_EQ(content_hash(late.scene), content_hash(graph.state()));
        }
    }
    EXPECT_GT(distinct.size(), 900u) << "the edits must really change the scene";
}

// Ops the scene graph never makes but the protocol allows: an image or a texture replaced in
// place (same id), which a tracer must take without a structural rebuild.
void replace_in_place(const SceneState& s, Pcg32& rng, Commit& commit) {
    if (!s.images.empty() && rng.next_u32() % 2 == 0) {
        Image img{"replaced", 2, 2, std::vector<uint8_t>(16)};
        for (uint8_t& b : img.rgba)
            b = uint8_t(rng.next_u32());
        commit.ops.push_back(AddImage{pick(rng, s.images), std::move(img)});
    }
    if (!s.textures.empty() && rng.next_u32() % 2 == 0) {
        const uint32_t id = pick(rng, s.textures);
        Texture t = s.textures.at(id);
        t.sampler.wrap_s = WrapMode(rng.next_u32() % 3);
        t.sampler.filter = rng.next_u32() % 2 ? FilterMode::nearest : FilterMode::linear;
        commit.ops.push_back(SetTexture{id, t});
    }
}

// Everything to_scene_model() writes: the objects by content hash (scene_state_from_model maps
// indices to ids in order, so the order counts) and what that mapping leaves out.
void expect_same_model(const SceneModel& patched, const SceneModel& whole, uint64_t frame) {
    EXPECT_EQ(content_hash(scene_state_from_model(patched)),
              content_hash(scene_state_from_model(whole)))
        << "frame " << frame;
    ASSERT_EQ(patched.instances.size(), whole.instances.size()) << "frame " << frame;
    for (std::size_t i = 0; i < whole.instances.size(); ++i)
        EXPECT_EQ(patched.instances[i].id, whole.instances[i].id) << "frame " << frame;
    EXPECT_EQ(patched.origin, whole.origin) << "frame " << frame;
}

TEST(ReplicaEquality, ATracersPatchedModelEqualsTheWholeConversion) {
    SceneGraph graph(make_cornell_box());
    tracer::Replica replica;
    ASSERT_TRUE(replica.apply(test::through_wire(make_snapshot(graph.state(), 0))).ok());
    SceneModel model;
    ASSERT_TRUE(replica.update_scene(model).structure);
    Pcg32 rng(77);
    std::vector<uint32_t> nodes;
    // Mostly edits in place, so most frames patch; now and then an add or a remove.
    const uint32_t kinds[] = {2, 2, 5, 6, 7, 7, 9, 10, 2, 7, 0, 8, 3, 1};
    int patched = 0;
    for (uint64_t frame = 1; frame <= 400; ++frame) {
        const int edits = 1 + int(rng.next_u32() % 3);
        const uint32_t last = frame % 10 == 0 ? 14 : 10;  // structural kinds every 10th frame
        for (int e = 0; e < edits; ++e)
            random_edit(graph, rng, nodes, kinds[rng.next_u32() % last]);
        graph.advance(double(frame) / 30.0);
        Commit commit = build_commit(graph.state(), graph.take_changes(), frame, frame - 1);
        replace_in_place(replica.state().scene, rng, commit);
        const Status applied = replica.apply(test::through_wire(commit));
        ASSERT_TRUE(applied.ok()) << "frame " << frame << ": " << applied.error().message;
        const tracer::SceneChanges changes = replica.update_scene(model);
        patched += changes.structure ? 0 : 1;
        expect_same_model(model, to_scene_model(replica.state().scene), frame);
    }
    EXPECT_GT(patched, 300) << "most frames must take the patch, not the whole conversion";
}

TEST(ReplicaEquality, CommitOnTheWrongBaseIsRefusedAndChangesNothing) {
    SceneGraph graph(make_cornell_box());
    ReplicaState replica;
    ASSERT_TRUE(apply_commit(replica, make_snapshot(graph.state(), 5)).ok());
    const uint64_t before = content_hash(replica.scene);
    Camera c;
    c.camera_to_world = glm::translate(Mat4(1.0f), Vec3(1, 2, 3));
    graph.set_camera(std::nullopt, c, true);
    const Commit wrong = build_commit(graph.state(), graph.take_changes(), 7, 6);
    const Status s = apply_commit(replica, wrong);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("base 6"), std::string::npos) << s.error().message;
    EXPECT_EQ(content_hash(replica.scene), before);
    EXPECT_EQ(replica.commit, 5u);
    ReplicaState fresh;
    EXPECT_FALSE(apply_commit(fresh, wrong).ok()) << "no snapshot yet";
}

TEST(CommitSize, GrowsWithWhatChangedNotWithTheScene) {
    SceneGraph graph(make_default_scene());
    graph.advance(0.0);
    (void)graph.take_changes();
    graph.advance(1.0 / 30.0);
    const std::size_t still =
        encode_commit(build_commit(graph.state(), graph.take_changes(), 2, 1)).total_bytes();
    EXPECT_LE(still, 64u) << "a static scene with a still camera";
    Camera c = graph.state().cameras.at(graph.state().active_camera);
    c.camera_to_world = glm::translate(c.camera_to_world, Vec3(0.1f, 0, 0));
    graph.set_camera(graph.state().active_camera, c, true);
    const std::size_t moved =
        encode_commit(build_commit(graph.state(), graph.take_changes(), 3, 2)).total_bytes();
    EXPECT_LE(moved, 256u) << "a camera move alone";
    EXPECT_GT(moved, still);
}

}  // namespace
}  // namespace pathfarm::coord
