// PFM stores rows bottom to top; FloatImage keeps row 0 at the top.
#include "common/film/pfm.h"

#include <bit>
#include <cstring>
#include <fstream>

namespace pathfarm {

Status write_pfm(const std::string& path, const FloatImage& image) {
    static_assert(std::endian::native == std::endian::little, "PFM writer assumes little endian");
    std::ofstream out(path, std::ios::binary);
    if (!out) return make_error(ErrorCode::io_error, "{}: cannot open for writing", path);
    out << "PF\n" << image.width << " " << image.height << "\n-1.0\n";
    for (int y = image.height - 1; y >= 0; --y)
        out.write(reinterpret_cast<const char*>(image.row(y)),
                  std::streamsize(sizeof(float) * 3 * image.width));
    if (!out) return make_error(ErrorCode::io_error, "{}: write failed", path);
    return {};
}

Result<FloatImage> read_pfm(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return make_error(ErrorCode::not_found, "{}: cannot open image", path);
    std::string magic;
    int width = 0, height = 0;
    double scale = 0.0;
    in >> magic >> width >> height >> scale;
    in.get();  // the single whitespace byte before the data
    if (magic != "PF" || width <= 0 || height <= 0 || width > 65536 || height > 65536 ||
        scale == 0.0)
        return make_error(ErrorCode::parse_error, "{}: not an RGB PFM file", path);
    FloatImage img(width, height);
    for (int y = height - 1; y >= 0; --y)
        in.read(reinterpret_cast<char*>(img.row(y)), std::streamsize(sizeof(float) * 3 * width));
    if (!in) return make_error(ErrorCode::parse_error, "{}: truncated PFM data", path);
    if (scale > 0.0) {  // big-endian data
        for (float& v : img.rgb)
            v = std::bit_cast<float>(__builtin_bswap32(std::bit_cast<uint32_t>(v)));
    }
    return img;
}

}  // namespace pathfarm
