// The browser client's WebSocket messages (docs/web.md, "Protocol"): the same frames and
// inputs as the native client protocol (frame number, the newest input it shows, the input's
// sequence number), in a fixed little-endian layout that a page reads with a DataView.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "common/base/result.h"
#include "coordinator/game/game.h"

namespace pathfarm::coord {

enum class WebCodec : uint8_t { jpeg = 0, h264 = 1 };

// Coordinator -> browser: a 48-byte header, then the encoded picture.
struct WebFrameHeader {
    WebCodec codec = WebCodec::jpeg;
    bool key = true;  // a picture a decoder can start at (every JPEG; H.264 IDR frames)
    uint16_t width = 0, height = 0;                // the picture's size
    uint16_t render_width = 0, render_height = 0;  // what workload scaling rendered
    uint16_t spp = 0;                              // samples per pixel this frame (0: none new)
    uint64_t frame = 0;
    uint64_t last_input_sequence = 0;  // the newest of this client's inputs the frame shows
    uint64_t sent_us = 0;              // the coordinator's clock when it was sent
};
inline constexpr std::size_t kWebFrameHeaderBytes = 48;
std::string encode_web_frame(const WebFrameHeader& header, std::string_view picture);
Result<WebFrameHeader> decode_web_frame_header(std::string_view message);

// Browser -> coordinator: 36 bytes: "PFWI", version 1, flags (bit 0: the action key), two
// zero bytes, the sequence number, then right, up, forward (m) and yaw, pitch (rad) as floats.
inline constexpr std::size_t kWebInputBytes = 36;
std::string encode_web_input(const PlayerInput& input);
// Bounded as every client's input (bounded_input); a message of any other size, magic,
// version or flag bits is an error naming what is wrong.
Result<PlayerInput> decode_web_input(std::string_view message);

}  // namespace pathfarm::coord
