// zlib's gz* API reads plain files unchanged, so one path serves both cases.
#include "common/scene/load/file_read.h"

#include <zlib.h>

namespace pathfarm {

Result<std::string> read_file_maybe_gzip(const std::string& path) {
    gzFile file = gzopen(path.c_str(), "rb");
    if (file == nullptr) return make_error(ErrorCode::not_found, "{}: cannot open file", path);
    gzbuffer(file, 1 << 17);
    std::string data;
    char chunk[1 << 16];
    for (;;) {
        const int n = gzread(file, chunk, sizeof(chunk));
        if (n < 0) {
            int code = 0;
            std::string what = gzerror(file, &code);
            gzclose(file);
            return make_error(ErrorCode::parse_error, "{}: corrupt compressed data ({})", path,
                              what);
        }
        if (n == 0) break;
        data.append(chunk, std::size_t(n));
    }
    int code = 0;
    const char* what = gzerror(file, &code);
    if (code != Z_OK && code != Z_STREAM_END) {
        std::string message = what;
        gzclose(file);
        return make_error(ErrorCode::parse_error, "{}: truncated or corrupt gzip data ({})", path,
                          message);
    }
    gzclose(file);
    return data;
}

}  // namespace pathfarm
