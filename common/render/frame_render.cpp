// The per-pixel sample loop.
#include "common/render/frame_render.h"

#include <algorithm>

namespace pathfarm {

void render_block(const PathTracer& tracer, const FrameSpec& spec, int x0, int x1, int y0, int y1,
                  float* out, std::size_t out_stride, SampleCounters& counters, FirstHit* hits,
                  std::size_t hits_stride) {
    const CameraRays camera_ray(spec.camera, spec.width, spec.height);
    for (int y = y0; y < y1; ++y) {
        float* row = out + std::size_t(y - y0) * out_stride;
        FirstHit* hit_row = hits ? hits + std::size_t(y - y0) * hits_stride : nullptr;
        for (int x = x0; x < x1; ++x) {
            glm::dvec3 sum(0.0);
            const uint32_t pixel_hash =
                PixelSampler::pixel_hash(uint32_t(x), uint32_t(y), spec.frame, spec.seed);
            const int samples = std::max(spec.samples_at(x, y), 1);
            for (int s = spec.first_sample; s < spec.first_sample + samples; ++s) {
                PixelSampler sampler(pixel_hash, uint32_t(s));
                const Vec2 jitter = sampler.next_2d();
                const Ray ray = camera_ray(float(x) + jitter.x, float(y) + jitter.y);
                sum += glm::dvec3(tracer.trace(ray, sampler, counters));
            }
            if (hit_row)
                hit_row[x - x0] = tracer.first_hit(camera_ray(x + 0.5f, y + 0.5f), counters);
            const double inv_spp = 1.0 / double(samples);
            float* p = row + 3 * (x - x0);
            p[0] = float(sum.x * inv_spp);
            p[1] = float(sum.y * inv_spp);
            p[2] = float(sum.z * inv_spp);
        }
    }
}

}  // namespace pathfarm
