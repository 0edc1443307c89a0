// Message framing: a 4-byte big-endian length, then the serialised Envelope. The length is
// checked against a hard maximum per connection role before anything is allocated.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "common/base/result.h"

namespace pathfarm::net {

// 2: truncation became its own message (FrameTruncation), FrameAssignment.truncate_at retired.
// 3: tiles carry the first hits an assignment asks for (the coordinator refuses tiles without
//    them, so an older tracer is refused at the handshake instead) and the update time.
// 4: first hits carry flags (FirstHit::kSharp), a byte plane more in first_hits_zstd.
// 5: assignments say whether next-event estimation chooses emitters through the light tree.
// 6: first hits carry the triangle and barycentrics of deformed surfaces (motion vectors).
// 7: instances say whether they are dynamic (tracers lay out their BVHs by it, so a tracer
//    that ignored it would render other bits).
// 8: assignments may give some pixels more samples than spp (FrameAssignment.extra_samples_zstd;
//    a tracer that ignored it would render other bits).
inline constexpr uint32_t kProtocolVersion = 9;
inline constexpr std::size_t kFrameHeaderBytes = 4;
// What a coordinator accepts from tracers (tiles of a whole frame at 4K stay far below) and
// from clients (input only); what peers accept from the coordinator (commit chunks, frames).
inline constexpr uint32_t kMaxFromTracerBytes = 64u << 20;
inline constexpr uint32_t kMaxFromClientBytes = 64u << 10;
inline constexpr uint32_t kMaxFromCoordinatorBytes = 128u << 20;

void write_frame_header(uint32_t payload_bytes, unsigned char out[kFrameHeaderBytes]);
// The payload length, or an error when it is 0 or exceeds max_bytes.
Result<uint32_t> read_frame_header(const unsigned char in[kFrameHeaderBytes], uint32_t max_bytes);
// Header + payload in one buffer, ready to write.
std::string frame(std::string_view payload);

}  // namespace pathfarm::net
