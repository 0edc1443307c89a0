// Fixed layouts, read and written byte by byte in little-endian order.
#include "coordinator/http/web_protocol.h"

#include <bit>
#include <cstring>

namespace pathfarm::coord {
namespace {

constexpr std::string_view kFrameMagic = "PFWF", kInputMagic = "PFWI";
constexpr uint8_t kVersion = 1;

template <typename T>
void put(std::string& out, T value) {
    static_assert(std::endian::native == std::endian::little, "the layout is little-endian");
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out.append(bytes, sizeof(T));
}

template <typename T>
T get(std::string_view in, std::size_t at) {
    T value;
    std::memcpy(&value, in.data() + at, sizeof(T));
    return value;
}

}  // namespace

std::string encode_web_frame(const WebFrameHeader& h, std::string_view picture) {
    std::string out;
    out.reserve(kWebFrameHeaderBytes + picture.size());
    out += kFrameMagic;
    put(out, kVersion);
    put(out, uint8_t(h.codec));
    put(out, uint8_t(h.key ? 1 : 0));  // flags
    put(out, uint8_t(0));
    for (const uint16_t v : {h.width, h.height, h.render_width, h.render_height, h.spp, uint16_t(0),
                             uint16_t(0), uint16_t(0)})
        put(out, v);
    for (const uint64_t v : {h.frame, h.last_input_sequence, h.sent_us})
        put(out, v);
    out += picture;  // header: 8 + 8 * 2 + 3 * 8 = kWebFrameHeaderBytes
    return out;
}

Result<WebFrameHeader> decode_web_frame_header(std::string_view m) {
    if (m.size() < kWebFrameHeaderBytes || m.substr(0, 4) != kFrameMagic ||
        get<uint8_t>(m, 4) != kVersion || get<uint8_t>(m, 5) > uint8_t(WebCodec::h264))
        return make_error(ErrorCode::parse_error, "web frame: not a version-1 frame header");
    WebFrameHeader h;
    h.codec = WebCodec(get<uint8_t>(m, 5));
    h.key = (get<uint8_t>(m, 6) & 1) != 0;
    h.width = get<uint16_t>(m, 8);
    h.height = get<uint16_t>(m, 10);
    h.render_width = get<uint16_t>(m, 12);
    h.render_height = get<uint16_t>(m, 14);
    h.spp = get<uint16_t>(m, 16);
    h.frame = get<uint64_t>(m, 24);
    h.last_input_sequence = get<uint64_t>(m, 32);
    h.sent_us = get<uint64_t>(m, 40);
    return h;
}

std::string encode_web_input(const PlayerInput& in) {
    std::string out;
    out += kInputMagic;
    put(out, kVersion);
    put(out, uint8_t(in.action ? 1 : 0));
    put(out, uint16_t(0));
    put(out, in.sequence);
    for (const float v : in.move)
        put(out, v);
    return out;
}

Result<PlayerInput> decode_web_input(std::string_view m) {
    if (m.size() != kWebInputBytes)
        return make_error(ErrorCode::parse_error, "web input: {} bytes, expected {}", m.size(),
                          kWebInputBytes);
    if (m.substr(0, 4) != kInputMagic || get<uint8_t>(m, 4) != kVersion)
        return make_error(ErrorCode::parse_error, "web input: not a version-1 input");
    if ((get<uint8_t>(m, 5) & ~1u) != 0 || get<uint16_t>(m, 6) != 0)
        return make_error(ErrorCode::parse_error, "web input: unknown flag bits");
    PlayerInput in;
    in.action = get<uint8_t>(m, 5) != 0;
    in.sequence = get<uint64_t>(m, 8);
    for (std::size_t k = 0; k < in.move.size(); ++k)
        in.move[k] = get<float>(m, 16 + 4 * k);
    return bounded_input(in);
}

}  // namespace pathfarm::coord
