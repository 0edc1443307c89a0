// H.264 frames for clients through libavcodec with libx264 (docs/web.md, "H.264"): a real-time
// stream (zerolatency tuning, no B-frames, sliced threads, an IDR frame every `key_interval`
// frames and on request): on the demo's 320x180 frames 3.4x fewer bytes than JPEG q90 at
// equal PSNR, 2.5x at equal SSIM (docs/web.md). The decoder is libavcodec's, for the native
// client and the benchmark. libav headers stay in the .cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/film/jpeg_codec.h"

namespace pathfarm {

struct H264Settings {
    int width = 0, height = 0;  // even
    double fps = 10.0;
    int key_interval = 120;  // frames between IDR frames when none is asked for
    int crf = 23;            // x264's constant rate factor: lower is better and bigger
    int threads = 1;         // > 1: sliced threads (every thread on each frame: no delay)
    std::string preset = "ultrafast";
    std::string profile = "baseline";  // or "main", "high" (CABAC, 8x8 transforms)
    std::string tune = "zerolatency";  // always includes zerolatency (no frame of delay)
    std::string x264_params = {};      // x264's own options over the preset: "trellis=1:ref=2"
};

// The stream the coordinator sends to H.264 clients (docs/web.md, "H.264"), `width` x `height`.
H264Settings h264_stream_settings(int width, int height);

struct H264Picture {
    std::string bytes;  // Annex B: start codes, SPS and PPS before every IDR frame
    bool key = false;   // an IDR frame: a decoder can start here
};

class H264Encoder {
public:
    // An error names the setting at fault (odd size, unknown preset, no libx264).
    static Result<std::unique_ptr<H264Encoder>> open(const H264Settings& settings);
    ~H264Encoder();
    const H264Settings& settings() const { return settings_; }
    // One sRGB frame (width*height*3, row 0 at the top) in, one picture out; `key` forces an
    // IDR frame (a new viewer, a lost frame, a cut).
    Result<H264Picture> encode(const std::vector<uint8_t>& rgb, bool key);

    struct Impl;

private:
    explicit H264Encoder(const H264Settings& s);
    H264Settings settings_;
    std::unique_ptr<Impl> impl_;
};

class H264Decoder {
public:
    static Result<std::unique_ptr<H264Decoder>> open();
    ~H264Decoder();
    // One picture of the stream in, the frame it shows out (sRGB, the encoder's size).
    Result<Rgb8Image> decode(const std::string& annex_b);

    struct Impl;

private:
    H264Decoder();
    std::unique_ptr<Impl> impl_;
};

}  // namespace pathfarm
