// The primary-hit G-buffer for reprojection and (next) the denoiser, made from the first hits
// the tracers return with their tiles (DESIGN.md, "The frame" step 6): the coordinator traces
// no rays of its own for it.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/film/first_hits.h"
#include "common/math/transform.h"
#include "common/scene/camera.h"

namespace pathfarm::coord {

struct GBuffer {
    int width = 0, height = 0;
    std::vector<float> distance;     // along the unit primary ray; +inf where the ray escapes
    std::vector<uint32_t> instance;  // instance id; kNoInstance where the ray escapes
    std::vector<Vec3> position;      // world-space hit point (undefined where it escapes)
    std::vector<Vec3> normal;        // shading normal facing the camera (zero where it escapes)
    std::vector<Rgb> albedo;         // base colour (zero where it escapes)
    std::vector<uint8_t> sharp;      // 1: the denoiser keeps the pixel's own light (FirstHit)
    std::vector<uint8_t> glossy;     // 1: FirstHit::kGlossy (its history lags the camera)
    // Triangle and barycentrics of the hit, on surfaces that deformed this frame (FirstHit);
    // kNone elsewhere. With upscaling, the nearest render pixel's.
    std::vector<uint32_t> primitive;
    std::vector<Vec2> barycentric;

    static constexpr uint32_t kNoInstance = 0;  // instance ids start at 1
    bool hit(std::size_t i) const { return instance[i] != kNoInstance; }
    void resize(int w, int h);       // every pixel a miss
    void size_planes(int w, int h);  // w x h, pixels left as they were or zero
    // Pixel i a miss: what the sky leaves (no instance, infinite distance, zeros).
    void set_miss(std::size_t i) {
        distance[i] = kInfinity;
        instance[i] = kNoInstance;
        position[i] = normal[i] = albedo[i] = Vec3(0.0f);
        sharp[i] = glossy[i] = 0;
        primitive[i] = FirstHit::kNone;
        barycentric[i] = Vec2(0.0f);
    }
};

// The G-buffer at width x height from the first hits of a hits_width x hits_height render
// (workload scaling may render smaller than the display): each pixel takes the nearest render
// pixel's hit, placed along its own centre ray at that hit's distance. The first hits' jitter
// moves a surface point by at most a pixel's footprint.
// `reuse`: a G-buffer no longer needed (TemporalAccumulator::take_spare_gbuffer), written
// over: of the same size, its planes need no allocation or clearing.
GBuffer gbuffer_from_first_hits(const std::vector<FirstHit>& hits, int hits_width, int hits_height,
                                const Camera& camera, int width, int height, GBuffer reuse = {});

// The same from a backend's own first hits at the display size, whose instances are SceneModel
// indices (pathfarm-render, benchmarks) rather than the scene graph's ids: index i becomes id
// i + 1, since 0 is the G-buffer's miss.
GBuffer gbuffer_from_backend_hits(std::vector<FirstHit> hits, const Camera& camera, int width,
                                  int height);

// Maps world points and directions to continuous pixel coordinates (pixel centres at +0.5):
// the inverse of generate_camera_ray. False when behind the camera.
// Inline: the temporal accumulator projects every pixel under a moving camera, and through a
// call its two results went by memory (a store-forwarding stall per pixel).
class CameraProjector {
public:
    CameraProjector(const Camera& camera, int width, int height);
    bool point(const Vec3& p, float& px, float& py) const {
        return camera_space(transform_point(world_to_camera_, p), px, py);
    }
    // A point at infinity: the sky.
    bool direction(const Vec3& d, float& px, float& py) const {
        return camera_space(transform_vector(world_to_camera_, d), px, py);
    }
    Vec3 eye() const { return eye_; }
    // point() for n points given as coordinate planes, and each one's distance from the eye
    // (glm::length(p - eye())): the same floats, operation for operation (glm's matrix product
    // and dot written out), in a loop that vectorises. `on[k]` is what point() returns; px and
    // py are meaningless where it is 0. Under a moving camera the temporal accumulator projects
    // a row at a time: pixel by pixel, the division and square root were 40 % of its blend.
    void points(const float* __restrict xs, const float* __restrict ys, const float* __restrict zs,
                int n, float* __restrict px, float* __restrict py, int32_t* __restrict on,
                float* __restrict distance) const {
        // In locals: the stores cannot change them, so the loop needs no alias checks.
        const Mat4 m = world_to_camera_;
        const Vec3 eye = eye_;
        const float sx_scale = inv_scale_x_, sy_scale = inv_scale_y_, hw = half_width_,
                    hh = half_height_;
        for (int k = 0; k < n; ++k) {
            const float x = xs[k], y = ys[k], z = zs[k];
            const float qx = (m[0][0] * x + m[1][0] * y) + (m[2][0] * z + m[3][0]);
            const float qy = (m[0][1] * x + m[1][1] * y) + (m[2][1] * z + m[3][1]);
            const float qz = (m[0][2] * x + m[1][2] * y) + (m[2][2] * z + m[3][2]);
            const float inv_depth = -1.0f / qz;
            const float sx = (qx * inv_depth * sx_scale + 1.0f) * hw;
            const float sy = (1.0f - qy * inv_depth * sy_scale) * hh;
            px[k] = sx;
            py[k] = sy;
            on[k] = qz < 0.0f && std::abs(sx) <= kLargest && std::abs(sy) <= kLargest ? 1 : 0;
            const float dx = x - eye.x, dy = y - eye.y, dz = z - eye.z;
            distance[k] = std::sqrt((dx * dx + dy * dy) + dz * dz);
        }
    }

private:
    static constexpr float kLargest = std::numeric_limits<float>::max();  // isfinite as a compare

    bool camera_space(const Vec3& q, float& px, float& py) const {
        if (!(q.z < 0.0f)) return false;      // the camera looks down -Z
        const float inv_depth = -1.0f / q.z;  // one division, not four
        px = (q.x * inv_depth * inv_scale_x_ + 1.0f) * half_width_;
        py = (1.0f - q.y * inv_depth * inv_scale_y_) * half_height_;
        return std::isfinite(px) && std::isfinite(py);
    }

    Mat4 world_to_camera_;
    Vec3 eye_;
    float inv_scale_x_, inv_scale_y_;  // 1 / tan of the half field of view, per axis
    float half_width_, half_height_;
};

}  // namespace pathfarm::coord
