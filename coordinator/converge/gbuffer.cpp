// The G-buffer from the tracers' first hits, and the inverse of generate_camera_ray.
#include "coordinator/converge/gbuffer.h"

#include <algorithm>

#include "common/math/transform.h"
#include "coordinator/converge/parallel_rows.h"

namespace pathfarm::coord {

void GBuffer::size_planes(int w, int h) {
    width = w;
    height = h;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    distance.resize(n), instance.resize(n), position.resize(n), normal.resize(n);
    albedo.resize(n), sharp.resize(n), glossy.resize(n), primitive.resize(n);
    barycentric.resize(n);
}

void GBuffer::resize(int w, int h) {
    size_planes(w, h);
    for (std::size_t i = 0; i < distance.size(); ++i)
        set_miss(i);
}

GBuffer gbuffer_from_first_hits(const std::vector<FirstHit>& hits, int hits_width, int hits_height,
                                const Camera& camera, int width, int height, GBuffer reuse) {
    GBuffer g = std::move(reuse);
    if (hits.size() != std::size_t(hits_width) * std::size_t(hits_height) || hits.empty()) {
        g.resize(width, height);
        return g;  // none: every pixel a miss, no history survives
    }
    // On the display's way to the screen (1.8 ms a frame in the demo, filled as misses first and
    // then one row after another): the planes sized (a memset, none when reused at the same
    // size), then every pixel written once, rows in parallel.
    g.size_planes(width, height);
    const CameraRays camera_ray(camera, width, height);
    parallel_rows(height, [&](int y) {
        const int hy = std::min(hits_height - 1, int((y + 0.5f) * hits_height / height));
        for (int x = 0; x < width; ++x) {
            const int hx = std::min(hits_width - 1, int((x + 0.5f) * hits_width / width));
            const FirstHit& h = hits[std::size_t(hy) * hits_width + hx];
            const std::size_t i = std::size_t(y) * width + x;
            if (!h.hit() || h.instance == GBuffer::kNoInstance) {
                g.set_miss(i);
                continue;
            }
            const Ray ray = camera_ray(x + 0.5f, y + 0.5f);
            g.distance[i] = h.distance;
            g.instance[i] = h.instance;
            g.position[i] = ray.o + ray.d * h.distance;
            g.normal[i] = h.normal;
            g.albedo[i] = h.albedo;
            g.sharp[i] = h.sharp() ? 1 : 0;
            g.glossy[i] = h.glossy() ? 1 : 0;
            g.primitive[i] = h.primitive;
            g.barycentric[i] = Vec2(h.u, h.v);
        }
    });
    return g;
}

GBuffer gbuffer_from_backend_hits(std::vector<FirstHit> hits, const Camera& camera, int width,
                                  int height) {
    for (FirstHit& h : hits)
        if (h.hit()) ++h.instance;
    return gbuffer_from_first_hits(hits, width, height, camera, width, height);
}

CameraProjector::CameraProjector(const Camera& camera, int width, int height)
    : world_to_camera_(glm::inverse(camera.camera_to_world)),
      eye_(transform_point(camera.camera_to_world, Vec3(0.0f))),
      half_width_(0.5f * float(width)),
      half_height_(0.5f * float(height)) {
    const float scale_y = std::tan(0.5f * camera.yfov_radians);
    inv_scale_y_ = 1.0f / scale_y;
    inv_scale_x_ = 1.0f / (scale_y * float(width) / float(height));
}

}  // namespace pathfarm::coord
