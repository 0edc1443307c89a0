// The tracer's frame worker without sockets: commits through the real wire codecs into the
// replica, and each kind of scene change reaches the backend as that kind of change (DESIGN.md,
// "The frame" step 5), with everything on the first scene and after structural edits.
#include "tracer-node/frame_worker.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/commit/commit_codec.h"
#include "common/film/first_hits.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/wire/messages.h"

namespace pathfarm::tracer {
namespace {

// Records what update_scene received; renders black rows, and first hits that cycle through
// the scene's instances, each on triangle 3 at barycentrics (0.25, 0.5).
class RecordingBackend final : public RenderBackend {
public:
    std::string name() const override { return "recording"; }
    Status set_scene(const SceneModel&) override { return {}; }
    Status update_scene(const SceneModel& scene, const SceneChanges& changes) override {
        updates.push_back(changes);
        instances = scene.instances.size();
        return {};
    }
    Result<RenderStats> render_rows(const RenderJob& job, float* out) override {
        const std::size_t pixels = std::size_t(job.y1 - job.y0) * job.frame.width;
        std::fill(out, out + pixels * 3, 0.0f);
        for (std::size_t i = 0; job.first_hits && i < pixels; ++i)
            job.first_hits[i] = FirstHit{
                1.0f, uint32_t(i % instances), Vec3(0, 0, 1), Rgb(0.5f), 0u, 3u, 0.25f, 0.5f};
        return RenderStats{};
    }
    std::vector<SceneChanges> updates;
    std::size_t instances = 0;
};

class FrameWorkerTest : public ::testing::Test {
protected:
    FrameWorkerTest()
        : worker_(
              options_, backend_, [this](std::string e) { tiles_.push_back(std::move(e)); },
              RenderControl{[] { return uint64_t(0); },
                            [](const wire::Assignment&, uint32_t) { return false; }}),
          state_(scene_state_from_model(make_default_scene())) {
        send(make_snapshot(state_, 0));
        render(0);
    }
    // Sends a commit as its envelopes, decoded as the tracer's inbox decodes them.
    void send(const Commit& c) {
        for (const std::string& e : wire::encode_commit_envelopes(encode_commit(c))) {
            auto m = wire::decode_for_tracer(e);
            ASSERT_TRUE(m.ok()) << m.error().message;
            ASSERT_TRUE(worker_.handle(*m).ok());
        }
    }
    void render(uint64_t frame, bool first_hits = false) {
        const wire::Assignment a{frame, frame, 0, 4, 16, 8, 1, 0, 2, 1.0f, first_hits};
        ASSERT_TRUE(worker_.handle(wire::TracerInbound{a}).ok());
    }
    // Applies one op as commit `frame` and returns what the backend was told at the next render.
    SceneChanges change(uint64_t frame, CommitOp op) {
        send(Commit{frame, frame - 1, false, {std::move(op)}});
        const std::size_t before = backend_.updates.size();
        render(frame);
        EXPECT_EQ(backend_.updates.size(), before + 1) << "frame " << frame;
        return backend_.updates.empty() ? SceneChanges{} : backend_.updates.back();
    }
    uint32_t first_instance_id() const { return state_.instances.begin()->first; }
    uint32_t emissive_material_id() const {
        for (const auto& [id, m] : state_.materials)
            if (m.is_emissive()) return id;
        ADD_FAILURE() << "builtin:default has emitters";
        return 0;
    }
    uint32_t plain_material_id() const {
        for (const auto& [id, m] : state_.materials)
            if (!m.is_emissive()) return id;
        return 0;
    }

    TracerOptions options_;
    RecordingBackend backend_;
    std::vector<std::string> tiles_;
    FrameWorker worker_;
    SceneState state_;
};

TEST_F(FrameWorkerTest, TheFirstSceneIsAllNewAndTilesComeBack) {
    ASSERT_EQ(backend_.updates.size(), 1u);
    EXPECT_TRUE(backend_.updates[0].structure);
    ASSERT_EQ(tiles_.size(), 1u);
    auto t = wire::decode_tile(tiles_[0]);
    ASSERT_TRUE(t.ok()) << t.error().message;
    EXPECT_EQ(t->unit_cost_us.size(), 1u) << "one 4-row unit, timed";
}

TEST_F(FrameWorkerTest, AMovedInstanceArrivesAsThatInstance) {
    const uint32_t id = first_instance_id();
    InstanceState moved = state_.instances.at(id);
    moved.transform = glm::translate(moved.transform, Vec3(0.1f, 0.0f, 0.0f));
    const SceneChanges c = change(1, SetInstance{id, moved});
    EXPECT_FALSE(c.structure);
    EXPECT_EQ(c.instances, std::vector<uint32_t>{0});
    EXPECT_TRUE(c.mesh_vertices.empty() && c.materials.empty() && c.textures.empty());
    EXPECT_FALSE(c.camera || c.settings || c.environment);
}

TEST_F(FrameWorkerTest, DeformedVerticesArriveAsThatMesh) {
    const uint32_t mesh = state_.meshes.begin()->first;
    const SceneChanges c =
        change(1, UpdateVertexRange{mesh, 0, {state_.meshes.at(mesh).positions[0]}, {}, {}});
    EXPECT_FALSE(c.structure);
    EXPECT_EQ(c.mesh_vertices, std::vector<uint32_t>{0});
    EXPECT_TRUE(c.instances.empty() && c.materials.empty());
}

TEST_F(FrameWorkerTest, MaterialAndLightEditsArriveAsMaterialsAndLights) {
    const uint32_t plain = plain_material_id();
    Material m = state_.materials.at(plain);
    m.roughness_factor = 0.123f;
    SceneChanges c = change(1, SetMaterial{plain, m});
    EXPECT_FALSE(c.structure);
    EXPECT_EQ(c.materials.size(), 1u);
    EXPECT_FALSE(c.lights) << "a non-emissive material";
    const uint32_t lamp = emissive_material_id();
    Material off = state_.materials.at(lamp);
    off.emissive_factor = Rgb(0.0f);  // the light is switched off
    c = change(2, SetMaterial{lamp, off});
    EXPECT_EQ(c.materials.size(), 1u);
    EXPECT_TRUE(c.lights);
}

TEST_F(FrameWorkerTest, TexturesCameraSettingsAndEnvironmentArriveAsSuch) {
    const uint32_t texture = state_.textures.begin()->first;
    SceneChanges c = change(1, SetTexture{texture, state_.textures.at(texture)});
    EXPECT_EQ(c.textures, std::vector<uint32_t>{0});
    EXPECT_FALSE(c.structure);
    // Recentring snaps to cells (scene_model.h): within its cell the camera moves alone.
    const double cell = recentre_cell(world_bounds(make_default_scene()));
    Camera cam = state_.cameras.at(state_.active_camera);
    const glm::dvec3 centre = glm::floor(glm::dvec3(cam.camera_to_world[3]) / cell + 0.5) * cell;
    cam.camera_to_world[3] = Vec4(Vec3(centre + 0.1 * cell), 1.0f);
    c = change(2, SetCamera{state_.active_camera, cam, true});
    EXPECT_TRUE(c.camera);
    EXPECT_TRUE(c.instances.empty()) << "a move within the camera's cell moves no instance";
    cam.camera_to_world[3].x += float(cell);  // into the next cell: every instance shifts
    c = change(3, SetCamera{state_.active_camera, cam, true});
    EXPECT_EQ(c.instances.size(), backend_.instances) << "camera-relative: every instance moved";
    c = change(4, SetSettings{RenderSettings{32, 16, 2, 3, 7}});
    EXPECT_TRUE(c.settings && !c.camera && c.instances.empty());
    c = change(5, SetEnvironment{Environment{}});
    EXPECT_TRUE(c.environment && c.lights);
}

TEST_F(FrameWorkerTest, AddingOrRemovingObjectsIsStructural) {
    EXPECT_TRUE(change(1, RemoveInstance{first_instance_id()}).structure);
    Mesh tri;
    tri.positions = {Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    tri.indices = {0, 1, 2};
    tri.material = int(plain_material_id());
    EXPECT_TRUE(change(2, AddMesh{9999, tri}).structure);
}

TEST_F(FrameWorkerTest, AnUnchangedSceneIsNotHandedToTheBackendAgain) {
    send(Commit{1, 0, false, {}});
    render(1);
    EXPECT_EQ(backend_.updates.size(), 1u);
}

// First hits carry the triangle and barycentrics only on instances whose mesh the frame's
// commit deformed (the coordinator reprojects those by their vertices' motion); elsewhere the
// planes stay empty, as zeros zstd removes.
TEST_F(FrameWorkerTest, FirstHitsNameTrianglesOnlyOfDeformedInstances) {
    const uint32_t mesh = state_.meshes.begin()->first;
    send(Commit{
        1, 0, false, {UpdateVertexRange{mesh, 0, {state_.meshes.at(mesh).positions[0]}, {}, {}}}});
    tiles_.clear();
    render(1, true);
    ASSERT_EQ(tiles_.size(), 1u);
    auto t = wire::decode_tile(tiles_[0]);
    ASSERT_TRUE(t.ok()) << t.error().message;
    auto hits = decode_first_hits(t->first_hits_zstd, 16 * 4);
    ASSERT_TRUE(hits.ok()) << hits.error().message;
    int deformed = 0, still = 0;
    for (const FirstHit& h : *hits) {
        ASSERT_TRUE(h.hit());
        if (state_.instances.at(h.instance).mesh == mesh) {
            ++deformed;
            EXPECT_EQ(h.primitive, 3u);
            EXPECT_EQ(h.u, 0.25f);
            EXPECT_EQ(h.v, 0.5f);
        } else {
            ++still;
            EXPECT_EQ(h.primitive, FirstHit::kNone);
            EXPECT_EQ(h.u, 0.0f);
            EXPECT_EQ(h.v, 0.0f);
        }
    }
    EXPECT_GT(deformed, 0);
    EXPECT_GT(still, 0);
}

}  // namespace
}  // namespace pathfarm::tracer
