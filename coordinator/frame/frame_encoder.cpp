// Frame encoders.
#include "coordinator/frame/frame_encoder.h"

#include "common/film/float_codec.h"
#include "common/film/image_io.h"
#include "common/film/jpeg_codec.h"
#include "coordinator/frame/parallel_image.h"

namespace pathfarm::coord {

Result<std::string> encode_frame(const FloatImage& image, FrameCodec codec, int jpeg_quality) {
    if (codec == FrameCodec::h264)
        return make_error(ErrorCode::invalid_argument, "H.264 is a stream: ClientHub encodes it");
    if (codec == FrameCodec::float_zstd)
        return compress_floats(image.rgb.data(), image.rgb.size(), 3);
    if (codec == FrameCodec::jpeg)
        return encode_jpeg(image.width, image.height, tonemap_to_srgb8_parallel(image),
                           jpeg_quality);
    auto png = encode_png(image.width, image.height, tonemap_to_srgb8_parallel(image));
    if (!png) return png.error();
    return std::string(png->begin(), png->end());
}

FrameCodec choose_codec(const std::vector<int>& accepted) {
    for (int c : accepted)
        if (c == int(FrameCodec::png) || c == int(FrameCodec::float_zstd) ||
            c == int(FrameCodec::jpeg) || c == int(FrameCodec::h264))
            return FrameCodec(c);
    return FrameCodec::jpeg;
}

}  // namespace pathfarm::coord
