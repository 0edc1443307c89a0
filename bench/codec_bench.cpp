// Frame codecs for clients (issue: the game in a browser): JPEG through libturbojpeg against
// H.264 through libx264, on a recorded sequence of frames as the farm sends them (sRGB after
// tonemapping). Per setting (JPEG quality, or H.264 CRF with the stream's settings), every
// frame is encoded, timed, decoded and compared with the uncompressed frame.
// Usage: pathfarm-codec-bench FOLDER_OF_PFM_FRAMES PRESET[:PROFILE[:TUNE[:X264_PARAMS]]] THREADS
//   QUALITIES CRFS (PRESET "stream": the coordinator's stream settings)
//   (QUALITIES and CRFS comma-separated). Prints CSV rows
//   `codec,setting,width,height,frames,encode_ms_median,encode_ms_p95,bytes_mean,psnr_mean,psnr_min,
//   ssim_mean` (SSIM of the luma).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "bench/bench_usage.h"
#include "common/base/timer.h"
#include "common/film/h264_codec.h"
#include "common/film/image_compare.h"
#include "common/film/image_io.h"
#include "common/film/jpeg_codec.h"
#include "common/film/tonemap.h"

using namespace pathfarm;

namespace {

struct Row {
    std::vector<double> ms, bytes, psnr, ssim;
};

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size())))];
}

double mean(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v)
        s += x;
    return s / double(v.size());
}

std::vector<int> numbers(const std::string& list) {
    std::vector<int> out;
    std::stringstream in(list);
    for (std::string item; std::getline(in, item, ',');)
        out.push_back(std::stoi(item));
    return out;
}

void print(const char* codec, int setting, int w, int h, const Row& r) {
    std::printf("%s,%d,%d,%d,%zu,%.4f,%.4f,%.1f,%.3f,%.3f,%.5f\n", codec, setting, w, h,
                r.ms.size(), percentile(r.ms, 0.5), percentile(r.ms, 0.95), mean(r.bytes),
                mean(r.psnr), *std::min_element(r.psnr.begin(), r.psnr.end()), mean(r.ssim));
}

int jpeg(const std::vector<std::vector<uint8_t>>& frames, int w, int h, int quality) {
    Row r;
    for (const auto& rgb : frames) {
        const Timer t;
        auto bytes = encode_jpeg(w, h, rgb, quality);
        r.ms.push_back(t.milliseconds());
        if (!bytes) return std::fprintf(stderr, "%s\n", bytes.error().message.c_str()), 1;
        auto back = decode_jpeg(*bytes);
        if (!back) return std::fprintf(stderr, "%s\n", back.error().message.c_str()), 1;
        r.bytes.push_back(double(bytes->size()));
        r.psnr.push_back(psnr8(back->rgb, rgb));
        r.ssim.push_back(ssim8(back->rgb, rgb, w, h));
    }
    print("jpeg", quality, w, h, r);
    return 0;
}

int h264(const std::vector<std::vector<uint8_t>>& frames, int w, int h, int crf,
         const std::string& preset, int threads) {
    // PRESET[:PROFILE[:TUNE[:X264_PARAMS]]], x264's options separated by '/' (':' splits here).
    // PRESET "stream": the coordinator's stream, the other fields overriding or adding to it.
    std::vector<std::string> parts;
    std::stringstream in(preset);
    for (std::string part; std::getline(in, part, ':');)
        parts.push_back(part);
    parts.resize(4);
    std::replace(parts[3].begin(), parts[3].end(), '/', ':');
    H264Settings s = h264_stream_settings(w, h);
    if (parts[0] != "stream")
        s = {w, h, 10.0, 100, crf, 1, parts[0], "baseline", "zerolatency", ""};
    s.crf = crf;
    s.threads = threads;
    if (!parts[1].empty()) s.profile = parts[1];
    if (!parts[2].empty()) s.tune = parts[2];
    if (!parts[3].empty()) s.x264_params += (s.x264_params.empty() ? "" : ":") + parts[3];
    auto encoder = H264Encoder::open(s);
    if (!encoder) return std::fprintf(stderr, "%s\n", encoder.error().message.c_str()), 1;
    auto decoder = H264Decoder::open();
    if (!decoder) return std::fprintf(stderr, "%s\n", decoder.error().message.c_str()), 1;
    Row r;
    for (const auto& rgb : frames) {
        const Timer t;
        auto picture = (*encoder)->encode(rgb, false);
        r.ms.push_back(t.milliseconds());
        if (!picture) return std::fprintf(stderr, "%s\n", picture.error().message.c_str()), 1;
        auto back = (*decoder)->decode(picture->bytes);
        if (!back) return std::fprintf(stderr, "%s\n", back.error().message.c_str()), 1;
        r.bytes.push_back(double(picture->bytes.size()));
        r.psnr.push_back(psnr8(back->rgb, rgb));
        r.ssim.push_back(ssim8(back->rgb, rgb, w, h));
    }
    print("h264", crf, w, h, r);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (int code = bench::usage_exit(
            argc, argv, argc == 6,
            "usage: pathfarm-codec-bench FOLDER PRESET THREADS QUALITIES CRFS\n"
            "  FOLDER: frame_*.pfm (a recorded sequence); QUALITIES, CRFS: 70,90\n");
        code >= 0)
        return code;
    std::vector<std::string> paths;
    std::error_code error;
    for (auto it = std::filesystem::directory_iterator(argv[1], error);
         !error && it != std::filesystem::directory_iterator(); it.increment(error))
        if (it->path().extension() == ".pfm") paths.push_back(it->path().string());
    if (error) return std::fprintf(stderr, "%s: %s\n", argv[1], error.message().c_str()), 2;
    std::sort(paths.begin(), paths.end());
    if (paths.empty()) return std::fprintf(stderr, "%s: no .pfm frames\n", argv[1]), 2;
    std::vector<std::vector<uint8_t>> frames;
    int w = 0, h = 0;
    for (const std::string& p : paths) {
        auto image = read_image(p);
        if (!image) return std::fprintf(stderr, "%s\n", image.error().message.c_str()), 1;
        w = image->width;
        h = image->height;
        frames.push_back(tonemap_to_srgb8(*image));
    }
    std::printf(
        "codec,setting,width,height,frames,encode_ms_median,encode_ms_p95,bytes_mean,"
        "psnr_mean,psnr_min,ssim_mean\n");
    for (int q : numbers(argv[4]))
        if (jpeg(frames, w, h, q)) return 1;
    for (int crf : numbers(argv[5]))
        if (h264(frames, w, h, crf, argv[2], std::stoi(argv[3]))) return 1;
    return 0;
}
