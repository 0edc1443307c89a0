// The commit codec: round trips, bounded chunks, and malformed input rejected with an error.
#include "common/commit/commit_codec.h"

#include <functional>

#include <gtest/gtest.h>

#include "common/scene/load/builtin_scenes.h"
#include "pathfarm/wire/v1/commit.pb.h"

namespace pathfarm {
namespace {

Commit big_commit() {
    const SceneState s = scene_state_from_model(make_default_scene());
    return make_snapshot(s, 9);
}

// Encodes and decodes `c`, applies both to empty replicas and expects equal scenes; returns
// the decoded commit and the replica it built.
std::pair<Commit, ReplicaState> round_trip(const Commit& c) {
    const EncodedCommit e = encode_commit(c);
    auto d = decode_commit(e.commit, e.chunks);
    EXPECT_TRUE(d.ok()) << d.error().message;
    if (!d.ok()) return {};
    ReplicaState a, b;
    EXPECT_TRUE(apply_commit(a, c).ok());
    EXPECT_TRUE(apply_commit(b, *d).ok());
    EXPECT_EQ(content_hash(a.scene), content_hash(b.scene));
    return {*d, b};
}

TEST(CommitCodec, RoundTripsASnapshotExactly) {
    const auto [d, replica] = round_trip(big_commit());
    EXPECT_EQ(d.frame, 9u);
    EXPECT_TRUE(d.is_snapshot);
}

TEST(CommitCodec, AlphaModesAndTextureTransformsRoundTrip) {
    SceneModel model = make_default_scene();
    Material& m = model.materials.at(0);
    m.alpha_mode = AlphaMode::mask;
    m.alpha_cutoff = 0.3f;
    m.emissive_texture.transform = UvTransform{Vec2(0.5f, -0.25f), 1.25f, Vec2(2.0f, 0.5f)};
    model.materials.at(1).alpha_mode = AlphaMode::blend;
    const auto [d, b] = round_trip(make_snapshot(scene_state_from_model(model), 3));
    const Material& back = b.scene.materials.at(0);
    EXPECT_EQ(back.alpha_mode, AlphaMode::mask);
    EXPECT_EQ(back.alpha_cutoff, 0.3f);
    EXPECT_EQ(back.emissive_texture.transform.offset, Vec2(0.5f, -0.25f));
    EXPECT_EQ(back.emissive_texture.transform.rotation, 1.25f);
    EXPECT_EQ(back.emissive_texture.transform.scale, Vec2(2.0f, 0.5f));
    EXPECT_EQ(b.scene.materials.at(1).alpha_mode, AlphaMode::blend);
}

// Dynamic instances (InstanceState::dynamic) stay dynamic on the replica: tracers lay out
// their BVHs by it, so a lost mark would change their bits.
TEST(CommitCodec, DynamicInstancesRoundTrip) {
    SceneModel model = make_default_scene();
    model.instances.at(1).dynamic = true;
    const auto [d, b] = round_trip(make_snapshot(scene_state_from_model(model), 4));
    int dynamic = 0;
    for (const auto& [id, inst] : b.scene.instances)
        dynamic += inst.dynamic ? 1 : 0;
    EXPECT_EQ(dynamic, 1);
    EXPECT_TRUE(b.scene.instances.at(1).dynamic);
}

// A decode error names the commit, the op's index and kind, and the field.
TEST(CommitCodec, DecodeErrorsNameTheOpAndTheField) {
    namespace pb = ::pathfarm::wire::v1;
    const auto decode_one = [](const std::function<void(pb::CommitOp&)>& fill) {
        pb::Commit w;
        w.set_frame(12);
        w.add_ops()->mutable_remove_mesh()->set_id(1);  // op 0 is fine
        fill(*w.add_ops());
        auto r = decode_commit(w.SerializeAsString(), {});
        return r.ok() ? std::string("decoded") : r.error().message;
    };
    EXPECT_EQ(decode_one([](pb::CommitOp& op) {
                  op.mutable_set_mesh_bvh()->mutable_inline_data()->set_nodes(std::string(31, 'x'));
              }),
              "commit 12: op 1 SetMeshBvh: nodes: 31 bytes, not a multiple of 32");
    EXPECT_EQ(decode_one([](pb::CommitOp& op) {
                  op.mutable_set_texture()->mutable_texture()->set_wrap_t(5);
              }),
              "commit 12: op 1 SetTexture: wrap_t: 5 is not one of the 3 values");
    EXPECT_EQ(decode_one([](pb::CommitOp& op) {
                  op.mutable_set_instance()->mutable_instance()->set_transform("short");
              }),
              "commit 12: op 1 SetInstance: transform: 5 bytes, not 64");
    EXPECT_EQ(decode_one([](pb::CommitOp& op) {
                  op.mutable_set_material()->mutable_material()->add_base_color_factor(1.0f);
              }),
              "commit 12: op 1 SetMaterial: base_color_factor: 1 values, not 4");
    EXPECT_EQ(decode_one([](pb::CommitOp& op) { op.mutable_add_mesh()->set_blob(3); }),
              "commit 12: op 1 AddMesh: blob 3 is not in the commit");
    EXPECT_EQ(decode_one([](pb::CommitOp&) {}),
              "commit 12: op 1 (unset): no op, or one this build does not know");
}

TEST(CommitCodec, BulkPayloadsTravelInBoundedChunks) {
    const EncodedCommit e = encode_commit(big_commit(), 8192);
    EXPECT_GT(e.chunks.size(), 10u);
    for (const std::string& chunk : e.chunks)
        EXPECT_LE(chunk.size(), 8192u + 64u);
    EXPECT_LT(e.commit.size(), 8192u) << "bulk data stays out of the command stream";
}

TEST(CommitCodec, MalformedInputIsAnError) {
    const EncodedCommit e = encode_commit(big_commit(), 8192);
    EXPECT_FALSE(decode_commit("\xff\xff\xff garbage", e.chunks).ok());
    std::vector<std::string> missing(e.chunks.begin(), e.chunks.end() - 1);
    EXPECT_FALSE(decode_commit(e.commit, missing).ok());
    std::vector<std::string> reordered = e.chunks;
    std::swap(reordered[0], reordered[1]);
    EXPECT_FALSE(decode_commit(e.commit, reordered).ok());
    std::vector<std::string> truncated = e.chunks;
    truncated.back().resize(truncated.back().size() / 2);
    EXPECT_FALSE(decode_commit(e.commit, truncated).ok());
    const EncodedCommit other = encode_commit(Commit{10, 9, false, {}});
    std::vector<std::string> foreign = e.chunks;
    foreign.push_back(encode_commit(big_commit()).chunks.front());
    EXPECT_FALSE(decode_commit(other.commit, foreign).ok()) << "chunks of another commit";
}

TEST(CommitCodec, BadVertexUpdateIsRefusedByApply) {
    ReplicaState r;
    ASSERT_TRUE(apply_commit(r, big_commit()).ok());
    Commit c{10, 9, false, {UpdateVertexRange{0, 1u << 30, {Vec3(1.0f)}, {}, {}}}};
    EXPECT_FALSE(apply_commit(r, c).ok());
    EXPECT_EQ(r.commit, 9u);
}

}  // namespace
}  // namespace pathfarm
