// libavcodec (libx264 inside) and libswscale for the sRGB <-> YUV 4:2:0 conversion.
#include "common/film/h264_codec.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <mutex>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

namespace pathfarm {
namespace {

// Warnings logged by libav on this thread while an encoder opens: libx264 only warns about an
// x264 option it cannot parse and goes on without it, which would silently measure or stream
// something else than was asked for.
thread_local std::string* t_open_warnings = nullptr;

void libav_log(void* object, int level, const char* format, va_list args) {
    if (t_open_warnings && level <= AV_LOG_WARNING) {
        char line[512];
        std::vsnprintf(line, sizeof line, format, args);
        t_open_warnings->append(line);
    } else if (level <= AV_LOG_FATAL) {
        av_log_default_callback(object, level, format, args);
    }
}

// libav prints to stderr on its own (x264's statistics at every close, the decoder's complaints
// about bad input); every failure that matters comes back as an error here instead.
void quiet_libav() {
    static std::once_flag once;
    std::call_once(once, [] {
        av_log_set_level(AV_LOG_FATAL);
        av_log_set_callback(libav_log);
    });
}

std::string av_error(int code) {
    char text[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, text, sizeof text);
    return text;
}

struct FrameDeleter {
    void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct PacketDeleter {
    void operator()(AVPacket* p) const { av_packet_free(&p); }
};
struct ContextDeleter {
    void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
};
struct SwsDeleter {
    void operator()(SwsContext* s) const { sws_freeContext(s); }
};

// Every picture converted with the same matrix the encoder signals (BT.601, limited range):
// decoders (browsers included) then invert exactly what was applied.
void tag_colours(AVCodecContext* c) {
    c->colorspace = AVCOL_SPC_SMPTE170M;
    c->color_range = AVCOL_RANGE_MPEG;
    c->color_primaries = AVCOL_PRI_BT709;
    c->color_trc = AVCOL_TRC_IEC61966_2_1;
}

// The conversions' rounding and chroma filters set a ceiling on the stream's PSNR: with bilinear
// filters and the fast paths, the round trip alone held the demo's frames to 39.6 dB (RGB PSNR);
// exact rounding and full-resolution chroma, bicubic both ways, lift it to 42.1 dB, which every
// bit rate gains from (bench/codec_bench.py). Browsers upsample the chroma themselves.
constexpr int kToYuvFlags = SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INP;
constexpr int kToRgbFlags = SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT;

}  // namespace

// x264's faster preset up to 320x240 (trellis quantisation, finer subpixel search, two
// references) with every partition size (4x4 inter blocks too); above it veryfast with faster's
// subpixel search (subme 4) and trellis, not faster itself (its second reference and wider
// motion search bought nothing there: 2.63x against veryfast's 2.68x, earlier frames). Both with a
// deblocking filter one step stronger than the default (it smooths what remains of the frames'
// noise, where the default left block edges) and adaptive quantisation at 0.7 of x264's strength:
// at 1.0 it spends bits on flat, noisy areas that neither PSNR nor SSIM see. On the demo's frames
// of 2026-12-04 (docs/web.md): 3.65x fewer bytes than JPEG q90 at equal PSNR at 320x180 (2.49x at
// equal SSIM), about 4 ms a frame; 3.19x at 640x360 (1.68x), veryfast's 2.77x (1.47x) for 1.63x its
// instructions, about 11 ms a frame. The High profile (CABAC, 8x8 transforms), zerolatency, and DCT
// decimation off (it zeroes sparse blocks: a rendered frame's residual noise). CRF 18 matches JPEG
// q90 in PSNR and SSIM at 320x180 (bench/codec_bench.py). The psnr tune with finer chroma gives
// more "at equal PSNR", but with a clearly lower SSIM than JPEG's: not what a player sees. An IDR
// frame every 10 s at 10 frames/s, and whenever a client joins or lost a picture.
H264Settings h264_stream_settings(int width, int height) {
    H264Settings s{width, height,     10.0,   100,           18,
                   1,     "veryfast", "high", "zerolatency", "no-dct-decimate=1:deblock=1,1"};
    if (width * height <= 320 * 240) {
        s.preset = "faster";
        s.x264_params += ":partitions=all:aq-strength=0.7";
    } else {
        s.x264_params += ":subme=4:trellis=1:aq-strength=0.7";
    }
    return s;
}

struct H264Encoder::Impl {
    std::unique_ptr<AVCodecContext, ContextDeleter> context;
    std::unique_ptr<AVFrame, FrameDeleter> frame;
    std::unique_ptr<AVPacket, PacketDeleter> packet{av_packet_alloc()};
    std::unique_ptr<SwsContext, SwsDeleter> to_yuv;
    int64_t next_pts = 0;
};

H264Encoder::H264Encoder(const H264Settings& s) : settings_(s), impl_(std::make_unique<Impl>()) {}
H264Encoder::~H264Encoder() = default;

Result<std::unique_ptr<H264Encoder>> H264Encoder::open(const H264Settings& s) {
    if (s.width <= 0 || s.height <= 0 || s.width % 2 || s.height % 2)
        return make_error(ErrorCode::invalid_argument, "H.264: {}x{}: sizes must be even", s.width,
                          s.height);
    if (s.tune.find("zerolatency") == std::string::npos)
        return make_error(ErrorCode::invalid_argument, "H.264: tune {}: needs zerolatency", s.tune);
    if (!(s.fps > 0.0) || s.key_interval < 1 || s.crf < 0 || s.crf > 51 || s.threads < 1)
        return make_error(ErrorCode::invalid_argument,
                          "H.264: fps > 0, key interval >= 1, crf in [0, 51], threads >= 1");
    quiet_libav();
    const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
    if (!codec) return make_error(ErrorCode::unsupported, "H.264: libavcodec has no libx264");
    std::unique_ptr<H264Encoder> e(new H264Encoder(s));
    Impl& m = *e->impl_;
    m.context.reset(avcodec_alloc_context3(codec));
    AVCodecContext* c = m.context.get();
    c->width = s.width;
    c->height = s.height;
    c->time_base = AVRational{1000, int(std::lround(s.fps * 1000.0))};
    c->framerate = AVRational{c->time_base.den, c->time_base.num};
    c->pix_fmt = AV_PIX_FMT_YUV420P;
    c->gop_size = s.key_interval;
    c->max_b_frames = 0;
    c->thread_count = s.threads;
    c->thread_type = FF_THREAD_SLICE;  // x264's sliced threads: no frame of delay per thread
    tag_colours(c);
    for (const auto& [key, value] : {std::pair{"preset", s.preset.c_str()},
                                     {"tune", s.tune.c_str()},
                                     {"profile", s.profile.c_str()},
                                     {"forced-idr", "1"}})
        if (const int r = av_opt_set(c->priv_data, key, value, 0); r < 0)
            return make_error(ErrorCode::invalid_argument, "H.264: {} {}: {}", key, value,
                              av_error(r));
    if (!s.x264_params.empty())
        if (const int r = av_opt_set(c->priv_data, "x264-params", s.x264_params.c_str(), 0); r < 0)
            return make_error(ErrorCode::invalid_argument, "H.264: x264 options {}: {}",
                              s.x264_params, av_error(r));
    av_opt_set_double(c->priv_data, "crf", s.crf, 0);
    std::string warnings;
    t_open_warnings = &warnings;
    const int opened = avcodec_open2(c, codec, nullptr);
    t_open_warnings = nullptr;
    if (opened < 0)
        return make_error(ErrorCode::invalid_argument, "H.264: opening libx264 ({} preset): {}",
                          s.preset, av_error(opened));
    if (const auto at = warnings.find("Error parsing option"); at != std::string::npos)
        return make_error(ErrorCode::invalid_argument, "H.264: x264 options {}: {}", s.x264_params,
                          warnings.substr(at, warnings.find('\n', at) - at));
    m.frame.reset(av_frame_alloc());
    m.frame->format = AV_PIX_FMT_YUV420P;
    m.frame->width = s.width;
    m.frame->height = s.height;
    if (const int r = av_frame_get_buffer(m.frame.get(), 0); r < 0)
        return make_error(ErrorCode::io_error, "H.264: frame buffer: {}", av_error(r));
    m.to_yuv.reset(sws_getContext(s.width, s.height, AV_PIX_FMT_RGB24, s.width, s.height,
                                  AV_PIX_FMT_YUV420P, kToYuvFlags, nullptr, nullptr, nullptr));
    if (!m.to_yuv) return make_error(ErrorCode::unsupported, "H.264: no RGB to YUV conversion");
    return e;
}

Result<H264Picture> H264Encoder::encode(const std::vector<uint8_t>& rgb, bool key) {
    Impl& m = *impl_;
    const int w = settings_.width, h = settings_.height;
    if (rgb.size() != std::size_t(w) * h * 3)
        return make_error(ErrorCode::invalid_argument, "H.264: {} bytes for a {}x{} frame",
                          rgb.size(), w, h);
    if (const int r = av_frame_make_writable(m.frame.get()); r < 0)
        return make_error(ErrorCode::io_error, "H.264: {}", av_error(r));
    const uint8_t* planes[1] = {rgb.data()};
    const int strides[1] = {3 * w};
    sws_scale(m.to_yuv.get(), planes, strides, 0, h, m.frame->data, m.frame->linesize);
    m.frame->pts = m.next_pts++;
    m.frame->pict_type = key ? AV_PICTURE_TYPE_I : AV_PICTURE_TYPE_NONE;
    if (const int r = avcodec_send_frame(m.context.get(), m.frame.get()); r < 0)
        return make_error(ErrorCode::io_error, "H.264: encoding: {}", av_error(r));
    H264Picture out;
    for (;;) {  // zerolatency: the frame's packet comes out at once
        const int r = avcodec_receive_packet(m.context.get(), m.packet.get());
        if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) break;
        if (r < 0) return make_error(ErrorCode::io_error, "H.264: encoding: {}", av_error(r));
        out.bytes.append(reinterpret_cast<const char*>(m.packet->data), m.packet->size);
        out.key = out.key || (m.packet->flags & AV_PKT_FLAG_KEY);
        av_packet_unref(m.packet.get());
    }
    return out;
}

struct H264Decoder::Impl {
    std::unique_ptr<AVCodecContext, ContextDeleter> context;
    std::unique_ptr<AVFrame, FrameDeleter> frame{av_frame_alloc()};
    std::unique_ptr<AVPacket, PacketDeleter> packet{av_packet_alloc()};
    std::unique_ptr<SwsContext, SwsDeleter> to_rgb;
};

H264Decoder::H264Decoder() : impl_(std::make_unique<Impl>()) {}
H264Decoder::~H264Decoder() = default;

Result<std::unique_ptr<H264Decoder>> H264Decoder::open() {
    quiet_libav();
    const AVCodec* codec = avcodec_find_decoder(AV_CODEC_ID_H264);
    if (!codec) return make_error(ErrorCode::unsupported, "H.264: libavcodec has no decoder");
    std::unique_ptr<H264Decoder> d(new H264Decoder());
    d->impl_->context.reset(avcodec_alloc_context3(codec));
    AVCodecContext* c = d->impl_->context.get();
    c->flags |= AV_CODEC_FLAG_LOW_DELAY;  // each picture out as soon as it is in
    c->thread_count = 1;
    if (const int r = avcodec_open2(c, codec, nullptr); r < 0)
        return make_error(ErrorCode::unsupported, "H.264: opening the decoder: {}", av_error(r));
    return d;
}

Result<Rgb8Image> H264Decoder::decode(const std::string& annex_b) {
    Impl& m = *impl_;
    if (const int r = av_new_packet(m.packet.get(), int(annex_b.size())); r < 0)
        return make_error(ErrorCode::io_error, "H.264: {}", av_error(r));
    std::memcpy(m.packet->data, annex_b.data(), annex_b.size());
    const int sent = avcodec_send_packet(m.context.get(), m.packet.get());
    av_packet_unref(m.packet.get());
    if (sent < 0) return make_error(ErrorCode::parse_error, "H.264: {}", av_error(sent));
    if (const int r = avcodec_receive_frame(m.context.get(), m.frame.get()); r < 0)
        return make_error(ErrorCode::parse_error, "H.264: no picture: {}", av_error(r));
    const AVFrame& f = *m.frame;
    m.to_rgb.reset(sws_getCachedContext(m.to_rgb.release(), f.width, f.height,
                                        AVPixelFormat(f.format), f.width, f.height,
                                        AV_PIX_FMT_RGB24, kToRgbFlags, nullptr, nullptr, nullptr));
    if (!m.to_rgb) return make_error(ErrorCode::unsupported, "H.264: no YUV to RGB conversion");
    Rgb8Image image{f.width, f.height, std::vector<uint8_t>(std::size_t(f.width) * f.height * 3)};
    uint8_t* planes[1] = {image.rgb.data()};
    const int strides[1] = {3 * f.width};
    sws_scale(m.to_rgb.get(), f.data, f.linesize, 0, f.height, planes, strides);
    av_frame_unref(m.frame.get());
    return image;
}

}  // namespace pathfarm
