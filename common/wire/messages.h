// The wire messages between coordinator, tracers and clients (proto/pathfarm/wire/v1), each as
// a plain struct with one codec used by both ends: encode_* gives a whole serialised Envelope,
// decode_* checks a received Envelope's kind and the message's own consistency and returns the
// struct or a one-line error. What depends on the receiver's state (does a tile fit the frame
// being assembled?) is the receiver's to check. Protobuf stays in messages.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "common/base/result.h"
#include "common/commit/commit_codec.h"
#include "common/math/types.h"
#include "common/wire/frame_codec.h"
#include "common/wire/light_sampling.h"

namespace pathfarm::wire {

// The largest frame width or height an assignment or a frame may carry.
inline constexpr uint32_t kMaxImageSide = 16384;

// Coordinator -> tracer: render rows [y0, y1) of `frame` on the replica at commit `commit`.
struct Assignment {
    uint64_t frame = 0, commit = 0;
    uint32_t y0 = 0, y1 = 0;
    uint32_t width = 0, height = 0;
    uint32_t spp = 1, seed = 0, max_depth = 8;
    float rr_scale = 1.0f;    // Russian-roulette survival scale in (0, 1] (workload scaling)
    bool first_hits = false;  // send each pixel's first hit with the tiles
    LightSampling light_sampling = LightSampling::power;
    // Samples beyond spp per pixel of the whole frame (FrameSpec::extra_samples), zstd-
    // compressed as common/film/extra_samples_codec.h writes them; empty for none.
    std::string extra_samples_zstd{};
};

// Coordinator -> tracer: the rows of `frame` from `row` on went to another tracer: stop before
// them (an earlier assignment of this frame that contains `row` now ends there).
struct Truncation {
    uint64_t frame = 0, commit = 0;
    uint32_t row = 0;
};

// Tracer -> coordinator: linear float32 RGB rows [y0, y1), zstd-compressed, with the time and
// the rays of every 4-row work unit in them.
struct Tile {
    uint64_t frame = 0, commit = 0;
    uint32_t y0 = 0, y1 = 0;
    std::string rgb_zstd;
    uint32_t raw_bytes = 0;
    double render_ms = 0.0;
    std::vector<uint32_t> unit_cost_us;
    std::vector<uint64_t> unit_rays;
    std::string first_hits_zstd;  // encode_first_hits, ids as the commit's; empty unless asked
    double update_ms = 0.0;       // replica and backend update before the frame (first tile)
};

// Client -> coordinator: one input, with its sequence number and send time for latency.
struct Input {
    uint64_t sequence = 0, timestamp_us = 0;
    std::optional<Mat4> camera_to_world;  // an absolute pose (finite), or none
    std::vector<float> move;              // relative move x, y, z (m) and yaw, pitch (rad)
    bool action = false;
};

// Coordinator -> client: one encoded frame and the newest input it shows.
struct EncodedFrame {
    uint64_t frame = 0;
    uint32_t width = 0, height = 0;
    FrameCodec codec = FrameCodec::jpeg;
    std::string data;
    uint64_t last_input_sequence = 0;
};

std::string encode_assignment(const Assignment& a);
std::string encode_truncation(const Truncation& t);
std::string encode_tile(const Tile& t);
std::string encode_input(const Input& in);
std::string encode_frame(const EncodedFrame& f);

Result<Tile> decode_tile(const std::string& envelope);
Result<Input> decode_input(const std::string& envelope);
Result<EncodedFrame> decode_frame(const std::string& envelope);

// A commit as the Envelopes that carry it: its bulk chunks first, the Commit message last
// (the bytes are wrapped, not parsed again).
std::vector<std::string> encode_commit_envelopes(const EncodedCommit& commit);

// A Commit or a BulkChunk as a tracer received it, parsed once; decode_commit
// (common/commit/commit_codec.h) turns a commit and the chunks of its frame into a Commit.
struct CommitPart {
    uint64_t frame = 0;
    std::shared_ptr<const ParsedCommit> parsed;
};
struct ChunkPart {
    uint64_t frame = 0;
    std::shared_ptr<const ParsedChunk> parsed;
};

// What a tracer receives from its coordinator, decoded (and validated) from one Envelope.
using TracerInbound = std::variant<CommitPart, ChunkPart, Assignment, Truncation>;
Result<TracerInbound> decode_for_tracer(const std::string& envelope);

}  // namespace pathfarm::wire
