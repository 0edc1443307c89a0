// One codec per wire message (common/wire/messages.h): every message survives a round trip,
// and malformed, misdirected or inconsistent envelopes are errors that say what was wrong.
#include "common/wire/messages.h"

#include <gtest/gtest.h>

#include "common/film/first_hits.h"
#include "common/net/framing.h"
#include "common/sampling/rng.h"
#include "pathfarm/wire/v1/envelope.pb.h"

namespace pathfarm::wire {
namespace {

namespace pb = ::pathfarm::wire::v1;

template <typename T>
T tracer_message(const std::string& envelope) {
    auto m = decode_for_tracer(envelope);
    EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().message);
    EXPECT_TRUE(m.ok() && std::holds_alternative<T>(*m));
    return m.ok() && std::holds_alternative<T>(*m) ? std::get<T>(*m) : T{};
}

Tile tile_of(uint32_t y0, uint32_t y1, uint32_t raw_bytes, double render_ms) {
    Tile t;
    t.frame = t.commit = 3;
    t.y0 = y0;
    t.y1 = y1;
    t.rgb_zstd = "x";
    t.raw_bytes = raw_bytes;
    t.render_ms = render_ms;
    return t;
}

template <typename T>
void expect_error(const Result<T>& r, const std::string& part) {
    ASSERT_FALSE(r.ok()) << "expected an error mentioning \"" << part << "\"";
    EXPECT_NE(r.error().message.find(part), std::string::npos) << r.error().message;
}

TEST(WireMessages, AssignmentRoundTripsAndIsChecked) {
    const Assignment a{
        7, 7, 8, 24, 320, 180, 4, 99, 6, 0.5f, true, LightSampling::tree, "extra map bytes"};
    const Assignment b = tracer_message<Assignment>(encode_assignment(a));
    EXPECT_EQ(b.frame, 7u);
    EXPECT_EQ(b.y0, 8u);
    EXPECT_EQ(b.y1, 24u);
    EXPECT_EQ(b.width, 320u);
    EXPECT_EQ(b.spp, 4u);
    EXPECT_EQ(b.seed, 99u);
    EXPECT_EQ(b.max_depth, 6u);
    EXPECT_EQ(b.rr_scale, 0.5f);
    EXPECT_TRUE(b.first_hits);
    EXPECT_EQ(b.light_sampling, LightSampling::tree);
    for (LightSampling s : {LightSampling::power, LightSampling::tree, LightSampling::automatic}) {
        Assignment c{1, 1, 0, 4, 8, 8};
        c.light_sampling = s;
        EXPECT_EQ(tracer_message<Assignment>(encode_assignment(c)).light_sampling, s);
    }
    EXPECT_EQ(b.extra_samples_zstd, "extra map bytes");
    EXPECT_TRUE(tracer_message<Assignment>(encode_assignment({1, 1, 0, 4, 8, 8}))
                    .extra_samples_zstd.empty());
    EXPECT_EQ(tracer_message<Assignment>(encode_assignment({1, 1, 0, 4, 8, 8})).light_sampling,
              LightSampling::power)
        << "absent: by power";
    EXPECT_FALSE(tracer_message<Assignment>(encode_assignment({1, 1, 0, 4, 8, 8})).first_hits);
    EXPECT_EQ(tracer_message<Assignment>(encode_assignment({1, 1, 0, 4, 8, 8})).rr_scale, 1.0f)
        << "absent roulette scale means 1";
    expect_error(decode_for_tracer(encode_assignment({1, 1, 4, 4, 8, 8})), "rows [4, 4)");
    expect_error(decode_for_tracer(encode_assignment({1, 1, 0, 12, 8, 8})), "rows [0, 12)");
    expect_error(decode_for_tracer(encode_assignment({1, 1, 0, 4, 0, 8})), "0x8");
    expect_error(decode_for_tracer(encode_assignment({1, 1, 0, 4, 8, 8, 0})), "spp 0");
    pb::Envelope e;  // encode_assignment never writes a scale above 1; a peer might
    e.set_version(net::kProtocolVersion);
    auto* w = e.mutable_assignment();
    w->set_y1(4);
    w->set_width(8);
    w->set_height(8);
    w->set_spp(1);
    w->set_rr_scale(2.0f);
    expect_error(decode_for_tracer(e.SerializeAsString()), "roulette scale 2");
    w->set_rr_scale(1.0f);
    w->set_light_sampling(pb::LightSampling(7));  // a newer peer's sampler, unknown here
    expect_error(decode_for_tracer(e.SerializeAsString()), "unknown light sampling 7");
}

TEST(WireMessages, TruncationIsItsOwnMessage) {
    const Truncation t = tracer_message<Truncation>(encode_truncation({5, 5, 48}));
    EXPECT_EQ(t.frame, 5u);
    EXPECT_EQ(t.row, 48u);
    expect_error(decode_for_tracer(encode_truncation({5, 5, 0})), "row 0");
}

TEST(WireMessages, TileRoundTripsAndIsChecked) {
    const Tile t{3, 3, 16, 24, "zstd-bytes", 192, 12.5, {100, 200}, {1000, 2000}, "hits", 1.5};
    auto d = decode_tile(encode_tile(t));
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d->y0, 16u);
    EXPECT_EQ(d->rgb_zstd, "zstd-bytes");
    EXPECT_EQ(d->first_hits_zstd, "hits");
    EXPECT_EQ(d->update_ms, 1.5);
    expect_error(decode_tile(encode_tile({3, 3, 0, 4, "x", 48, 1.0, {}, {}, {}, -2.0})),
                 "update time -2");
    EXPECT_EQ(d->render_ms, 12.5);
    EXPECT_EQ(d->unit_cost_us, (std::vector<uint32_t>{100, 200}));
    EXPECT_EQ(d->unit_rays, (std::vector<uint64_t>{1000, 2000}));
    expect_error(decode_tile(encode_tile(tile_of(24, 16, 0, 0.0))), "rows [24, 16)");
    expect_error(decode_tile(encode_tile({3, 3, 0, 4, "x", 48, 1.0, {1, 2}, {}, {}, 0.0})),
                 "2 unit costs and 0 unit rays for 1 units");
    expect_error(decode_tile(encode_tile(tile_of(0, 4, 48, -1.0))), "render time -1");
    expect_error(decode_tile(encode_tile(tile_of(0, 4, 47, 1.0))), "47 raw bytes");
    expect_error(decode_tile(encode_truncation({1, 1, 4})), "tile expected");
    expect_error(decode_tile("\\xff\\xff garbage"), "malformed");
}

TEST(WireMessages, InputRoundTripsAndNonFinitePosesAreDropped) {
    Input in{42, 123456, Mat4(2.0f), {0.1f, 0.0f, -0.2f, 0.3f, 0.0f}, true};
    auto d = decode_input(encode_input(in));
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d->sequence, 42u);
    EXPECT_EQ(d->timestamp_us, 123456u);
    ASSERT_TRUE(d->camera_to_world.has_value());
    EXPECT_EQ((*d->camera_to_world)[1][1], 2.0f);
    EXPECT_EQ(d->move, in.move);
    EXPECT_TRUE(d->action);
    Mat4 bad(1.0f);
    bad[3][0] = std::nanf("");
    in.camera_to_world = bad;
    EXPECT_FALSE(decode_input(encode_input(in))->camera_to_world.has_value());
    in.move.assign(6, 0.0f);
    expect_error(decode_input(encode_input(in)), "6 move values");
    pb::Envelope e;
    e.set_version(net::kProtocolVersion);
    e.mutable_input()->set_camera_to_world("short");
    expect_error(decode_input(e.SerializeAsString()), "camera_to_world has 5 bytes");
}

TEST(WireMessages, EncodedFrameRoundTripsAndIsChecked) {
    const EncodedFrame f{9, 320, 180, FrameCodec::png, "png-bytes", 77};
    auto d = decode_frame(encode_frame(f));
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d->frame, 9u);
    EXPECT_EQ(d->codec, FrameCodec::png);
    EXPECT_EQ(d->data, "png-bytes");
    EXPECT_EQ(d->last_input_sequence, 77u);
    expect_error(decode_frame(encode_frame({9, 320, 180, FrameCodec(7), "x"})), "codec 7");
    expect_error(decode_frame(encode_frame({9, 0, 180, FrameCodec::jpeg, "x"})), "0x180");
    expect_error(decode_frame(encode_frame({9, 4, 4, FrameCodec::jpeg, ""})), "0 bytes");
}

TEST(WireMessages, CommitsAreParsedOnceAndReassembledFromTheirChunks) {
    Commit c;
    c.frame = 4;
    c.base_commit = 3;
    c.ops.push_back(SetInstance{2, {1, Mat4(3.0f)}});
    Mesh big;
    big.positions.assign(40000, Vec3(1.0f));  // a blob over several chunks
    c.ops.push_back(AddMesh{1, big});
    const std::vector<std::string> envelopes = encode_commit_envelopes(encode_commit(c, 65536));
    ASSERT_GT(envelopes.size(), 2u);
    std::vector<std::shared_ptr<const ParsedChunk>> chunks;
    for (std::size_t k = 0; k + 1 < envelopes.size(); ++k)
        chunks.push_back(tracer_message<ChunkPart>(envelopes[k]).parsed);
    const CommitPart part = tracer_message<CommitPart>(envelopes.back());
    EXPECT_EQ(part.frame, 4u);
    auto decoded = decode_commit(*part.parsed, chunks);
    ASSERT_TRUE(decoded.ok()) << decoded.error().message;
    EXPECT_EQ(decoded->base_commit, 3u);
    ASSERT_EQ(decoded->ops.size(), 2u);
    EXPECT_EQ(std::get<AddMesh>(decoded->ops[1]).mesh.positions.size(), 40000u);
    chunks.pop_back();  // a chunk lost on the way
    expect_error(decode_commit(*part.parsed, chunks), "incomplete");
}

TEST(WireMessages, MessagesNotForTracersAreRefused) {
    expect_error(decode_for_tracer(encode_tile(tile_of(0, 4, 48, 1.0))), "not for tracers");
    expect_error(decode_for_tracer("garbage"), "malformed");
}

// Tile.first_hits_zstd: every plane survives, ids and flags exactly, the rest to half
// precision; a payload of another pixel count is an error.
TEST(FirstHitsCodec, EveryPlaneSurvivesTheRoundTrip) {
    Pcg32 rng(11);
    std::vector<FirstHit> hits(300);
    for (FirstHit& h : hits) {
        if (rng.next_float() < 0.2f) continue;  // a miss
        h = FirstHit{1.0f + 50.0f * rng.next_float(),
                     rng.next_u32(),
                     Vec3(rng.next_float(), -rng.next_float(), rng.next_float()),
                     Rgb(rng.next_float(), rng.next_float(), rng.next_float()),
                     rng.next_float() < 0.5f ? FirstHit::kSharp : 0u,
                     rng.next_float() < 0.5f ? FirstHit::kNone : rng.next_u32(),
                     rng.next_float(),
                     rng.next_float()};
    }
    const std::string wire = encode_first_hits(hits.data(), hits.size());
    auto back = decode_first_hits(wire, hits.size());
    ASSERT_TRUE(back.ok()) << back.error().message;
    for (std::size_t i = 0; i < hits.size(); ++i) {
        const FirstHit &a = hits[i], &b = (*back)[i];
        EXPECT_EQ(a.distance, b.distance);
        EXPECT_EQ(a.instance, b.instance);
        EXPECT_EQ(a.flags, b.flags);
        EXPECT_EQ(a.primitive, b.primitive);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(a.normal[c], b.normal[c], 1e-3f);
            EXPECT_NEAR(a.albedo[c], b.albedo[c], 1e-3f);
        }
        EXPECT_NEAR(a.u, b.u, 1e-3f);
        EXPECT_NEAR(a.v, b.v, 1e-3f);
    }
    EXPECT_FALSE(decode_first_hits(wire, hits.size() + 1).ok());
    EXPECT_FALSE(decode_first_hits(wire, hits.size() - 1).ok());
}

}  // namespace
}  // namespace pathfarm::wire
