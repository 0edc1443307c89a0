#include "client/frame_output.h"

#include <fstream>

#include "common/film/float_codec.h"
#include "common/film/h264_codec.h"
#include "common/film/image_io.h"
#include "common/film/jpeg_codec.h"
#include "common/film/tonemap.h"

namespace pathfarm::client {

Result<DecodedFrame> decode_image(const wire::EncodedFrame& f, H264Decoder& video) {
    DecodedFrame d{int(f.width), int(f.height), {}, {}};  // sizes checked by wire::decode_frame
    if (f.codec == wire::FrameCodec::float_zstd) {
        auto rgb = decompress_floats(f.data, std::size_t(d.width) * d.height * 3);
        if (!rgb) return rgb.error();
        d.linear = FloatImage(d.width, d.height);
        d.linear->rgb = std::move(*rgb);
        d.srgb8 = tonemap_to_srgb8(*d.linear);
        return d;
    }
    int w = 0, h = 0;
    if (f.codec == wire::FrameCodec::h264) {
        auto picture = video.decode(f.data);
        if (!picture)
            return make_error(ErrorCode::parse_error, "frame {}: {}", f.frame,
                              picture.error().message);
        w = picture->width;
        h = picture->height;
        d.srgb8 = std::move(picture->rgb);
    } else if (f.codec == wire::FrameCodec::jpeg) {
        auto jpeg = decode_jpeg(f.data);
        if (!jpeg) return jpeg.error();
        w = jpeg->width;
        h = jpeg->height;
        d.srgb8 = std::move(jpeg->rgb);
    } else {  // png
        auto png = decode_rgba8(reinterpret_cast<const unsigned char*>(f.data.data()),
                                f.data.size(), "frame.png");
        if (!png) return png.error();
        w = png->width;
        h = png->height;
        d.srgb8.resize(std::size_t(w) * h * 3);
        for (std::size_t i = 0; i < std::size_t(w) * h; ++i)
            for (int c = 0; c < 3; ++c)
                d.srgb8[i * 3 + c] = png->rgba[i * 4 + c];
    }
    if (w != d.width || h != d.height)
        return make_error(ErrorCode::parse_error, "frame {}: image is {}x{}, frame {}x{}", f.frame,
                          w, h, d.width, d.height);
    return d;
}

Status write_frame(const ClientOptions& o, const wire::EncodedFrame& f, const DecodedFrame& d) {
    if (o.out_dir.empty()) return {};
    const std::string base = fmt::format("{}/frame_{:06d}", o.out_dir, f.frame);
    if (d.linear) return write_image(base + ".exr", *d.linear);
    if (f.codec == wire::FrameCodec::h264) {  // the frame as shown, and the playable stream
        std::ofstream(o.out_dir + "/stream.h264", std::ios::binary | std::ios::app) << f.data;
        auto png = encode_png(d.width, d.height, d.srgb8);
        if (!png) return png.error();
        std::ofstream(base + ".png", std::ios::binary)
            .write(reinterpret_cast<const char*>(png->data()), std::streamsize(png->size()));
        return {};
    }
    // Keep the coordinator's bytes.
    std::ofstream(base + (f.codec == wire::FrameCodec::png ? ".png" : ".jpg"), std::ios::binary)
        << f.data;
    return {};
}

}  // namespace pathfarm::client
