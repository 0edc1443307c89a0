// zstd one-shot compression; the decompressed size is checked before allocating.
#include "common/film/float_codec.h"

#include <zstd.h>

namespace pathfarm {

std::string compress_bytes(const void* data, std::size_t bytes, int level) {
    std::string out(ZSTD_compressBound(bytes), '\0');
    const std::size_t n = ZSTD_compress(out.data(), out.size(), data, bytes, level);
    out.resize(ZSTD_isError(n) ? 0 : n);
    return out;
}

Status decompress_bytes(const std::string& data, void* out, std::size_t bytes, const char* what) {
    const unsigned long long size = ZSTD_getFrameContentSize(data.data(), data.size());
    if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size != bytes)
        return make_error(ErrorCode::parse_error, "{}: {} bytes announced, {} expected", what, size,
                          bytes);
    const std::size_t n = ZSTD_decompress(out, bytes, data.data(), data.size());
    if (ZSTD_isError(n) || n != bytes)
        return make_error(ErrorCode::parse_error, "{}: {}", what,
                          ZSTD_isError(n) ? ZSTD_getErrorName(n) : "short");
    return {};
}

std::string compress_floats(const float* values, std::size_t count, int level) {
    return compress_bytes(values, count * sizeof(float), level);
}

Result<std::vector<float>> decompress_floats(const std::string& data, std::size_t expected_count) {
    std::vector<float> out(expected_count);
    const Status s =
        decompress_bytes(data, out.data(), expected_count * sizeof(float), "compressed pixels");
    if (!s) return s.error();
    return out;
}

}  // namespace pathfarm
