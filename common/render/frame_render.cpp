// The per-pixel sample loop, a run of neighbouring pixels at a time so that their camera rays
// are traced as one coherent packet.
#include "common/render/frame_render.h"

#include <algorithm>

namespace pathfarm {
namespace {

constexpr int kRun = Intersector::kCoherentWidth;

// Pixels [x, x + n) of row y (n <= kRun): the k-th camera rays of all n pixels are traced as
// one packet, then the centre rays (when `hits`) as another, and each pixel that takes a k-th
// sample follows its path on from there. A packet's answers may differ from single rays' where
// two triangles tie for the closest hit (its arithmetic differs by an ulp), so a packet always
// holds the same rays: the run's, whichever pixels take extra samples, and a pixel's value is
// a function of its run's camera rays, never of the map or the row split (docs/determinism.md).
void render_run(const PathTracer& tracer, const FrameSpec& spec, const CameraRays& camera_ray,
                int x, int n, int y, float* out, SampleCounters& counters, FirstHit* hits) {
    uint32_t hash[kRun];
    int samples[kRun];
    glm::dvec3 sum[kRun];
    int most = 0;
    for (int i = 0; i < n; ++i) {
        hash[i] = PixelSampler::pixel_hash(uint32_t(x + i), uint32_t(y), spec.frame, spec.seed);
        samples[i] = std::max(spec.samples_at(x + i, y), 1);
        sum[i] = glm::dvec3(0.0);
        most = std::max(most, samples[i]);
    }
    Ray rays[kRun];
    Hit found_hit[kRun];
    bool found[kRun];
    PixelSampler sampler[kRun];
    for (int k = 0; k < most; ++k) {
        for (int i = 0; i < n; ++i) {
            sampler[i] = PixelSampler(hash[i], uint32_t(spec.first_sample + k));
            const Vec2 jitter = sampler[i].next_2d();
            rays[i] = camera_ray(float(x + i) + jitter.x, float(y) + jitter.y);
        }
        tracer.kernel().intersect_coherent(rays, n, found_hit, found);
        for (int i = 0; i < n; ++i)
            if (k < samples[i])
                sum[i] += glm::dvec3(
                    tracer.trace(rays[i], {found[i], found_hit[i]}, sampler[i], counters));
    }
    if (hits) {
        for (int i = 0; i < n; ++i)
            rays[i] = camera_ray(float(x + i) + 0.5f, float(y) + 0.5f);
        tracer.kernel().intersect_coherent(rays, n, found_hit, found);
        for (int i = 0; i < n; ++i)
            hits[i] = tracer.first_hit(rays[i], {found[i], found_hit[i]}, counters);
    }
    for (int i = 0; i < n; ++i) {
        const double inv_spp = 1.0 / double(samples[i]);
        float* p = out + 3 * i;
        p[0] = float(sum[i].x * inv_spp);
        p[1] = float(sum[i].y * inv_spp);
        p[2] = float(sum[i].z * inv_spp);
    }
}

}  // namespace

void render_block(const PathTracer& tracer, const FrameSpec& spec, int x0, int x1, int y0, int y1,
                  float* out, std::size_t out_stride, SampleCounters& counters, FirstHit* hits,
                  std::size_t hits_stride) {
    const CameraRays camera_ray(spec.camera, spec.width, spec.height);
    for (int y = y0; y < y1; ++y) {
        float* row = out + std::size_t(y - y0) * out_stride;
        FirstHit* hit_row = hits ? hits + std::size_t(y - y0) * hits_stride : nullptr;
        for (int x = x0; x < x1; x += kRun)
            render_run(tracer, spec, camera_ray, x, std::min(kRun, x1 - x), y, row + 3 * (x - x0),
                       counters, hit_row ? hit_row + (x - x0) : nullptr);
    }
}

}  // namespace pathfarm
