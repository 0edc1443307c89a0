// Length-prefix framing.
#include "common/net/framing.h"

namespace pathfarm::net {

void write_frame_header(uint32_t n, unsigned char out[kFrameHeaderBytes]) {
    out[0] = static_cast<unsigned char>(n >> 24);
    out[1] = static_cast<unsigned char>(n >> 16);
    out[2] = static_cast<unsigned char>(n >> 8);
    out[3] = static_cast<unsigned char>(n);
}

Result<uint32_t> read_frame_header(const unsigned char in[kFrameHeaderBytes], uint32_t max_bytes) {
    const uint32_t n = (uint32_t(in[0]) << 24) | (uint32_t(in[1]) << 16) | (uint32_t(in[2]) << 8) |
                       uint32_t(in[3]);
    if (n == 0) return make_error(ErrorCode::parse_error, "empty message");
    if (n > max_bytes)
        return make_error(ErrorCode::invalid_argument,
                          "message of {} bytes exceeds the limit of {}", n, max_bytes);
    return n;
}

std::string frame(std::string_view payload) {
    std::string out(kFrameHeaderBytes + payload.size(), '\0');
    write_frame_header(uint32_t(payload.size()), reinterpret_cast<unsigned char*>(out.data()));
    out.replace(kFrameHeaderBytes, payload.size(), payload);
    return out;
}

}  // namespace pathfarm::net
