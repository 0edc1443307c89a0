// Extra-sample maps to and from their wire form.
#include "common/film/extra_samples_codec.h"

#include "common/film/float_codec.h"

namespace pathfarm {

std::string encode_extra_samples(const std::vector<uint8_t>& map) {
    return compress_bytes(map.data(), map.size());
}

Result<std::vector<uint8_t>> decode_extra_samples(const std::string& data, int width, int height) {
    if (width <= 0 || height <= 0)
        return make_error(ErrorCode::invalid_argument, "extra samples for a {}x{} frame", width,
                          height);
    std::vector<uint8_t> map(std::size_t(width) * std::size_t(height));
    if (Status s = decompress_bytes(data, map.data(), map.size(), "extra samples"); !s)
        return s.error();
    for (std::size_t i = 0; i < map.size(); ++i)
        if (map[i] > kMaxExtraSamples)
            return make_error(ErrorCode::parse_error,
                              "extra samples: {} for pixel ({}, {}), at most {}", int(map[i]),
                              i % std::size_t(width), i / std::size_t(width), kMaxExtraSamples);
    return map;
}

}  // namespace pathfarm
