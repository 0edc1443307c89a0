// The wire messages' codecs (messages.h): encode beside decode for each message.
#include "common/wire/messages.h"

#include <cmath>
#include <cstring>

#include "common/base/work_unit.h"
#include "common/commit/codec_internal.h"
#include "common/net/framing.h"
#include "pathfarm/wire/v1/envelope.pb.h"

namespace pathfarm::wire {
namespace {

namespace pb = ::pathfarm::wire::v1;

pb::Envelope envelope() {
    pb::Envelope e;
    e.set_version(net::kProtocolVersion);
    return e;
}

Result<pb::Envelope> parse(const std::string& bytes, pb::Envelope::BodyCase expected,
                           const char* what) {
    pb::Envelope e;
    if (!e.ParseFromString(bytes))
        return make_error(ErrorCode::parse_error, "{}: malformed envelope", what);
    if (e.body_case() != expected)
        return make_error(ErrorCode::parse_error, "{} expected, got envelope body {}", what,
                          int(e.body_case()));
    return e;
}

// An Envelope holding an already-serialised message in field `field`: protobuf's encoding of
// an embedded message is its tag, its length and its bytes, so no re-parse is needed.
std::string envelope_with(int field, const std::string& message) {
    std::string out = envelope().SerializeAsString();
    out.push_back(char((field << 3) | 2));
    for (std::size_t n = message.size();; n >>= 7) {
        out.push_back(char((n & 0x7f) | (n >= 0x80 ? 0x80 : 0)));
        if (n < 0x80) break;
    }
    return out + message;
}

Result<Assignment> to_assignment(const pb::FrameAssignment& w) {
    Assignment a{w.frame(),
                 w.commit(),
                 w.y0(),
                 w.y1(),
                 w.width(),
                 w.height(),
                 w.spp(),
                 w.seed(),
                 w.max_depth(),
                 w.rr_scale(),
                 w.first_hits(),
                 LightSampling::power,
                 w.extra_samples_zstd()};
    switch (w.light_sampling()) {
        case pb::LIGHT_SAMPLING_POWER:
            break;
        case pb::LIGHT_SAMPLING_TREE:
            a.light_sampling = LightSampling::tree;
            break;
        case pb::LIGHT_SAMPLING_AUTO:
            a.light_sampling = LightSampling::automatic;
            break;
        default:
            return make_error(ErrorCode::parse_error, "assignment: unknown light sampling {}",
                              int(w.light_sampling()));
    }
    if (a.rr_scale == 0.0f) a.rr_scale = 1.0f;  // absent: full survival
    if (a.width == 0 || a.height == 0 || a.width > kMaxImageSide || a.height > kMaxImageSide ||
        a.y0 >= a.y1 || a.y1 > a.height)
        return make_error(ErrorCode::parse_error, "assignment: rows [{}, {}) of a {}x{} frame",
                          a.y0, a.y1, a.width, a.height);
    if (a.spp == 0 || a.spp > (1u << 20) || a.max_depth > 1024 ||
        !(a.rr_scale > 0.0f && a.rr_scale <= 1.0f))
        return make_error(ErrorCode::parse_error,
                          "assignment: spp {}, max depth {} or roulette scale {} out of range",
                          a.spp, a.max_depth, a.rr_scale);
    return a;
}

}  // namespace

std::string encode_assignment(const Assignment& a) {
    pb::Envelope e = envelope();
    auto* w = e.mutable_assignment();
    w->set_frame(a.frame);
    w->set_commit(a.commit);
    w->set_y0(a.y0);
    w->set_y1(a.y1);
    w->set_width(a.width);
    w->set_height(a.height);
    w->set_spp(a.spp);
    w->set_seed(a.seed);
    w->set_max_depth(a.max_depth);
    if (a.rr_scale < 1.0f) w->set_rr_scale(a.rr_scale);
    w->set_first_hits(a.first_hits);
    w->set_light_sampling(a.light_sampling == LightSampling::tree ? pb::LIGHT_SAMPLING_TREE
                          : a.light_sampling == LightSampling::automatic
                              ? pb::LIGHT_SAMPLING_AUTO
                              : pb::LIGHT_SAMPLING_POWER);
    w->set_extra_samples_zstd(a.extra_samples_zstd);
    return e.SerializeAsString();
}

std::string encode_truncation(const Truncation& t) {
    pb::Envelope e = envelope();
    e.mutable_truncation()->set_frame(t.frame);
    e.mutable_truncation()->set_commit(t.commit);
    e.mutable_truncation()->set_row(t.row);
    return e.SerializeAsString();
}

std::string encode_tile(const Tile& t) {
    pb::Envelope e = envelope();
    auto* w = e.mutable_tile();
    w->set_frame(t.frame);
    w->set_commit(t.commit);
    w->set_y0(t.y0);
    w->set_y1(t.y1);
    w->set_rgb_zstd(t.rgb_zstd);
    w->set_raw_bytes(t.raw_bytes);
    w->set_render_ms(t.render_ms);
    for (uint32_t us : t.unit_cost_us)
        w->add_unit_cost_us(us);
    for (uint64_t rays : t.unit_rays)
        w->add_unit_rays(rays);
    w->set_first_hits_zstd(t.first_hits_zstd);
    w->set_update_ms(t.update_ms);
    return e.SerializeAsString();
}
Result<Tile> decode_tile(const std::string& bytes) {
    auto e = parse(bytes, pb::Envelope::kTile, "tile");
    if (!e) return e.error();
    const pb::Tile& w = e->tile();
    Tile t{w.frame(),
           w.commit(),
           w.y0(),
           w.y1(),
           w.rgb_zstd(),
           w.raw_bytes(),
           w.render_ms(),
           {w.unit_cost_us().begin(), w.unit_cost_us().end()},
           {w.unit_rays().begin(), w.unit_rays().end()},
           w.first_hits_zstd(),
           w.update_ms()};
    const std::size_t units =
        (std::size_t(t.y1 - std::min(t.y0, t.y1)) + kRowsPerWorkUnit - 1) / kRowsPerWorkUnit;
    if (t.y0 >= t.y1 || t.y1 > kMaxImageSide)
        return make_error(ErrorCode::parse_error, "tile: rows [{}, {})", t.y0, t.y1);
    if (t.unit_cost_us.size() > units || t.unit_rays.size() > units)
        return make_error(ErrorCode::parse_error,
                          "tile: {} unit costs and {} unit rays for {} units",
                          t.unit_cost_us.size(), t.unit_rays.size(), units);
    if (!std::isfinite(t.render_ms) || t.render_ms < 0.0 || !std::isfinite(t.update_ms) ||
        t.update_ms < 0.0 || t.raw_bytes % (3 * sizeof(float)) != 0)
        return make_error(ErrorCode::parse_error,
                          "tile: render time {} ms, update time {} ms or {} raw bytes", t.render_ms,
                          t.update_ms, t.raw_bytes);
    return t;
}

std::string encode_input(const Input& in) {
    pb::Envelope e = envelope();
    auto* w = e.mutable_input();
    w->set_sequence(in.sequence);
    w->set_timestamp_us(in.timestamp_us);
    if (in.camera_to_world)
        w->set_camera_to_world(
            std::string(reinterpret_cast<const char*>(&(*in.camera_to_world)[0][0]), sizeof(Mat4)));
    for (float m : in.move)
        w->add_move(m);
    w->set_action(in.action);
    return e.SerializeAsString();
}
Result<Input> decode_input(const std::string& bytes) {
    auto e = parse(bytes, pb::Envelope::kInput, "input");
    if (!e) return e.error();
    const pb::InputEvent& w = e->input();
    if (w.move_size() > 5)
        return make_error(ErrorCode::parse_error, "input: {} move values, at most 5",
                          w.move_size());
    if (!w.camera_to_world().empty() && w.camera_to_world().size() != sizeof(Mat4))
        return make_error(ErrorCode::parse_error, "input: camera_to_world has {} bytes, not {}",
                          w.camera_to_world().size(), sizeof(Mat4));
    Input in{w.sequence(),
             w.timestamp_us(),
             std::nullopt,
             {w.move().begin(), w.move().end()},
             w.action()};
    if (!w.camera_to_world().empty()) {
        Mat4 m;
        std::memcpy(&m[0][0], w.camera_to_world().data(), sizeof(Mat4));
        const float* v = &m[0][0];
        if (std::all_of(v, v + 16, [](float x) { return std::isfinite(x); }))
            in.camera_to_world = m;  // a pose with NaN/Inf is no pose
    }
    return in;
}

std::string encode_frame(const EncodedFrame& f) {
    pb::Envelope e = envelope();
    auto* w = e.mutable_frame();
    w->set_frame(f.frame);
    w->set_width(f.width);
    w->set_height(f.height);
    w->set_codec(pb::FrameCodec(int(f.codec)));
    w->set_data(f.data);
    w->set_last_input_sequence(f.last_input_sequence);
    return e.SerializeAsString();
}
Result<EncodedFrame> decode_frame(const std::string& bytes) {
    auto e = parse(bytes, pb::Envelope::kFrame, "frame");
    if (!e) return e.error();
    const pb::EncodedFrame& w = e->frame();
    if (w.codec() != pb::FRAME_CODEC_PNG && w.codec() != pb::FRAME_CODEC_FLOAT_ZSTD &&
        w.codec() != pb::FRAME_CODEC_JPEG && w.codec() != pb::FRAME_CODEC_H264)
        return make_error(ErrorCode::parse_error, "frame {}: codec {} unknown", w.frame(),
                          int(w.codec()));
    if (w.width() == 0 || w.height() == 0 || w.width() > kMaxImageSide ||
        w.height() > kMaxImageSide || w.data().empty())
        return make_error(ErrorCode::parse_error, "frame {}: {}x{} with {} bytes", w.frame(),
                          w.width(), w.height(), w.data().size());
    return EncodedFrame{w.frame(),
                        w.width(),
                        w.height(),
                        FrameCodec(int(w.codec())),
                        std::move(*e->mutable_frame()->mutable_data()),
                        w.last_input_sequence()};
}

std::vector<std::string> encode_commit_envelopes(const EncodedCommit& commit) {
    std::vector<std::string> out;
    for (const std::string& c : commit.chunks)
        out.push_back(envelope_with(pb::Envelope::kChunkFieldNumber, c));
    out.push_back(envelope_with(pb::Envelope::kCommitFieldNumber, commit.commit));
    return out;
}

Result<TracerInbound> decode_for_tracer(const std::string& bytes) {
    pb::Envelope e;
    if (!e.ParseFromString(bytes))
        return make_error(ErrorCode::parse_error, "malformed envelope from the coordinator");
    switch (e.body_case()) {
        case pb::Envelope::kCommit: {  // moved out of the envelope, not copied or re-parsed
            auto parsed = std::make_shared<ParsedCommit>();
            parsed->message.Swap(e.mutable_commit());
            return TracerInbound{CommitPart{parsed->message.frame(), std::move(parsed)}};
        }
        case pb::Envelope::kChunk: {
            auto parsed = std::make_shared<ParsedChunk>();
            parsed->message.Swap(e.mutable_chunk());
            return TracerInbound{ChunkPart{parsed->message.frame(), std::move(parsed)}};
        }
        case pb::Envelope::kAssignment: {
            auto a = to_assignment(e.assignment());
            if (!a) return a.error();
            return TracerInbound{*a};
        }
        case pb::Envelope::kTruncation: {
            const pb::FrameTruncation& t = e.truncation();
            if (t.row() == 0 || t.row() > kMaxImageSide)
                return make_error(ErrorCode::parse_error, "truncation of frame {} at row {}",
                                  t.frame(), t.row());
            return TracerInbound{Truncation{t.frame(), t.commit(), t.row()}};
        }
        default:
            return make_error(ErrorCode::parse_error,
                              "envelope body {} is not for tracers (commit, chunk, assignment or "
                              "truncation)",
                              int(e.body_case()));
    }
}

}  // namespace pathfarm::wire
