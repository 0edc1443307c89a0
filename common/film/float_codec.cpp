// zstd one-shot compression; the decompressed size is checked before allocating.
#include "common/film/float_codec.h"

#include <zstd.h>

namespace pathfarm {

std::string compress_floats(const float* values, std::size_t count, int level) {
    const std::size_t bytes = count * sizeof(float);
    std::string out(ZSTD_compressBound(bytes), '\0');
    const std::size_t n = ZSTD_compress(out.data(), out.size(), values, bytes, level);
    out.resize(ZSTD_isError(n) ? 0 : n);
    return out;
}

Result<std::vector<float>> decompress_floats(const std::string& data, std::size_t expected_count) {
    const unsigned long long size = ZSTD_getFrameContentSize(data.data(), data.size());
    if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN ||
        size != expected_count * sizeof(float))
        return make_error(ErrorCode::parse_error,
                          "compressed pixels: {} bytes announced, {} expected", size,
                          expected_count * sizeof(float));
    std::vector<float> out(expected_count);
    const std::size_t n = ZSTD_decompress(out.data(), size, data.data(), data.size());
    if (ZSTD_isError(n) || n != size)
        return make_error(ErrorCode::parse_error, "compressed pixels: {}",
                          ZSTD_isError(n) ? ZSTD_getErrorName(n) : "short");
    return out;
}

}  // namespace pathfarm
