// Rendering a block of pixels of one frame: the unit every backend's thread pool hands out.
#pragma once

#include <cstddef>
#include <cstdint>

#include "common/render/path_tracer.h"
#include "common/scene/camera.h"

namespace pathfarm {

struct FrameSpec {
    int width = 0;
    int height = 0;
    uint32_t frame = 0;
    uint32_t seed = 0;
    int spp = 1;
    int first_sample = 0;  // samples [first_sample, first_sample + spp) of each pixel
    Camera camera;
    // Samples some pixels take beyond spp (workload scaling spends idle time where history is
    // short: coordinator/pacing/extra_samples.h): width x height bytes, row-major over the whole
    // frame, or null for none. Pixel p renders samples [first_sample, first_sample + spp +
    // extra_samples[p]), so its value does not depend on which rows a tracer was given.
    const uint8_t* extra_samples = nullptr;

    int samples_at(int x, int y) const {
        return spp + (extra_samples ? int(extra_samples[std::size_t(y) * width + x]) : 0);
    }
};

// Renders pixels [x0, x1) x [y0, y1) into out, where out points at pixel (x0, y0) and rows are
// out_stride floats apart. Each pixel is the box-filtered mean of spec.samples_at(x, y) samples
// (uniform jitter inside the pixel square), accumulated in double. `hits`, when given, points at
// pixel (x0, y0) of a first-hit image with rows hits_stride pixels apart and receives what each
// pixel's centre ray meets first: the same surfaces every frame for a still view, as reprojection
// needs (a jittered sample's would flip between the surfaces at every edge).
void render_block(const PathTracer& tracer, const FrameSpec& spec, int x0, int x1, int y0, int y1,
                  float* out, std::size_t out_stride, SampleCounters& counters,
                  FirstHit* hits = nullptr, std::size_t hits_stride = 0);

}  // namespace pathfarm
