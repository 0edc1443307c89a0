// First-hit planes: half floats (half.h packs them as glm::packHalf1x16 does and unpacks them
// as glm::unpackHalf1x16 does), then one zstd frame (float_codec).
#include "common/film/first_hits.h"

#include <cstring>

#include "common/film/float_codec.h"
#include "common/math/half.h"

namespace pathfarm {
namespace {

constexpr std::size_t kBytesPerHit = 2 * 4 + 6 * 2 + 1 + 4 + 2 * 2;

template <typename T>
void put(std::string& out, std::size_t& at, T value) {
    std::memcpy(out.data() + at, &value, sizeof(T));
    at += sizeof(T);
}

template <typename T>
T get(const std::string& in, std::size_t& at) {
    T value;
    std::memcpy(&value, in.data() + at, sizeof(T));
    at += sizeof(T);
    return value;
}

}  // namespace

std::string encode_first_hits(const FirstHit* hits, std::size_t count) {
    std::string raw(count * kBytesPerHit, '\0');
    std::size_t at = 0;
    for (std::size_t i = 0; i < count; ++i)
        put(raw, at, hits[i].distance);
    for (std::size_t i = 0; i < count; ++i)
        put(raw, at, hits[i].instance);
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < count; ++i)
            put(raw, at, uint16_t(half_bits(hits[i].normal[c])));
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < count; ++i)
            put(raw, at, uint16_t(half_bits(hits[i].albedo[c])));
    for (std::size_t i = 0; i < count; ++i)
        put(raw, at, uint8_t(hits[i].flags));
    for (std::size_t i = 0; i < count; ++i)
        put(raw, at, hits[i].primitive);
    for (std::size_t i = 0; i < count; ++i)
        put(raw, at, uint16_t(half_bits(hits[i].u)));
    for (std::size_t i = 0; i < count; ++i)
        put(raw, at, uint16_t(half_bits(hits[i].v)));
    return compress_bytes(raw.data(), raw.size());
}

Result<std::vector<FirstHit>> decode_first_hits(const std::string& data, std::size_t count) {
    std::string raw(count * kBytesPerHit, '\0');
    if (Status s = decompress_bytes(data, raw.data(), raw.size(), "first hits"); !s)
        return s.error();
    std::vector<FirstHit> hits(count);
    std::size_t at = 0;
    for (FirstHit& h : hits)
        h.distance = get<float>(raw, at);
    for (FirstHit& h : hits)
        h.instance = get<uint32_t>(raw, at);
    for (int c = 0; c < 3; ++c)
        for (FirstHit& h : hits)
            h.normal[c] = half_to_float(get<uint16_t>(raw, at));
    for (int c = 0; c < 3; ++c)
        for (FirstHit& h : hits)
            h.albedo[c] = half_to_float(get<uint16_t>(raw, at));
    for (FirstHit& h : hits)
        h.flags = get<uint8_t>(raw, at);
    for (FirstHit& h : hits)
        h.primitive = get<uint32_t>(raw, at);
    for (FirstHit& h : hits)
        h.u = half_to_float(get<uint16_t>(raw, at));
    for (FirstHit& h : hits)
        h.v = half_to_float(get<uint16_t>(raw, at));
    return hits;
}

}  // namespace pathfarm
