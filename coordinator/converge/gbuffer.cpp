// G-buffer tracing (TBB over rows) and the inverse of generate_camera_ray.
#include "coordinator/converge/gbuffer.h"

#include <algorithm>
#include <map>

#include <tbb/parallel_for.h>

#include "common/math/transform.h"
#include "coordinator/query/ray_query.h"

namespace pathfarm::coord {

namespace {

struct PixelRect {
    int x0, y0, x1, y1;  // [x0, x1) x [y0, y1)
};

void trace_pixel(const AccelSnapshot& accel, const Camera& camera, GBuffer& g, int x, int y) {
    const Ray ray = generate_camera_ray(camera, g.width, g.height, x + 0.5f, y + 0.5f);
    const auto hit = closest_hit(accel, ray);
    const std::size_t i = std::size_t(y) * g.width + x;
    g.distance[i] = hit ? hit->distance : kInfinity;
    g.instance[i] = hit ? hit->instance : GBuffer::kNoInstance;
    g.position[i] = hit ? hit->point : Vec3(0.0f);
}

// Corner c (0..7) of box b: bit 0 picks x, bit 1 y, bit 2 z.
Vec3 box_corner(const Bounds3f& b, int c) {
    return {c & 1 ? b.upper.x : b.lower.x, c & 2 ? b.upper.y : b.lower.y,
            c & 4 ? b.upper.z : b.lower.z};
}

// World box of an instance: its mesh's BVH root box through its transform.
Bounds3f world_box(const AccelSnapshot& accel, const InstanceAccel& inst) {
    Bounds3f out;
    const Bounds3f b = accel.meshes.at(inst.mesh)->bvh.bounds();
    if (b.empty()) return out;
    for (int c = 0; c < 8; ++c)
        out.extend(transform_point(inst.to_world, box_corner(b, c)));
    return out;
}

}  // namespace

GBuffer trace_gbuffer(const AccelSnapshot& accel, const Camera& camera, int width, int height) {
    GBuffer g;
    g.width = width;
    g.height = height;
    const std::size_t n = std::size_t(width) * height;
    g.distance.assign(n, kInfinity);
    g.instance.assign(n, GBuffer::kNoInstance);
    g.position.assign(n, Vec3(0.0f));
    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x)
            trace_pixel(accel, camera, g, x, y);
    });
    return g;
}

GBuffer update_gbuffer(const GBuffer& previous, const AccelSnapshot& previous_accel,
                       const AccelSnapshot& accel, const Camera& camera,
                       std::size_t* traced_pixels) {
    const int w = previous.width, h = previous.height;
    // Boxes of what changed, before and after.
    std::map<uint32_t, const InstanceAccel*> before, after;
    for (const InstanceAccel& i : previous_accel.instances)
        before[i.id] = &i;
    for (const InstanceAccel& i : accel.instances)
        after[i.id] = &i;
    std::vector<Bounds3f> boxes;
    for (const auto& [id, inst] : after) {
        const auto it = before.find(id);
        const bool same = it != before.end() && it->second->to_world == inst->to_world &&
                          it->second->mesh == inst->mesh &&
                          previous_accel.meshes.at(inst->mesh) == accel.meshes.at(inst->mesh);
        if (same) continue;
        boxes.push_back(world_box(accel, *inst));
        if (it != before.end()) boxes.push_back(world_box(previous_accel, *it->second));
    }
    for (const auto& [id, inst] : before)
        if (!after.count(id)) boxes.push_back(world_box(previous_accel, *inst));
    const CameraProjector project(camera, w, h);
    std::vector<PixelRect> rects;
    for (const Bounds3f& b : boxes) {
        if (b.empty()) continue;
        float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
        for (int c = 0; c < 8; ++c) {
            float px, py;
            if (!project.point(box_corner(b, c), px, py)) {
                if (traced_pixels) *traced_pixels = std::size_t(w) * h;
                return trace_gbuffer(accel, camera, w, h);  // the box reaches behind the eye
            }
            x0 = std::min(x0, px), y0 = std::min(y0, py);
            x1 = std::max(x1, px), y1 = std::max(y1, py);
        }
        const PixelRect r{std::max(0, int(std::floor(x0)) - 1),
                          std::max(0, int(std::floor(y0)) - 1), std::min(w, int(std::ceil(x1)) + 1),
                          std::min(h, int(std::ceil(y1)) + 1)};
        if (r.x0 < r.x1 && r.y0 < r.y1) rects.push_back(r);
    }
    std::vector<uint8_t> stale(std::size_t(w) * h, 0);  // rectangles may overlap
    for (const PixelRect& r : rects)
        for (int y = r.y0; y < r.y1; ++y)
            std::fill_n(&stale[std::size_t(y) * w + r.x0], r.x1 - r.x0, uint8_t(1));
    GBuffer g = previous;
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x)
            if (stale[std::size_t(y) * w + x]) trace_pixel(accel, camera, g, x, y);
    });
    const std::size_t traced = std::size_t(std::count(stale.begin(), stale.end(), uint8_t(1)));
    if (traced_pixels) *traced_pixels = traced;
    return g;
}

CameraProjector::CameraProjector(const Camera& camera, int width, int height)
    : world_to_camera_(glm::inverse(camera.camera_to_world)),
      eye_(transform_point(camera.camera_to_world, Vec3(0.0f))),
      scale_y_(std::tan(0.5f * camera.yfov_radians)),
      width_(width),
      height_(height) {
    scale_x_ = scale_y_ * float(width) / float(height);
}

bool CameraProjector::camera_space(const Vec3& q, float& px, float& py) const {
    if (!(q.z < 0.0f)) return false;  // the camera looks down -Z
    px = (q.x / -q.z / scale_x_ + 1.0f) * 0.5f * float(width_);
    py = (1.0f - q.y / -q.z / scale_y_) * 0.5f * float(height_);
    return std::isfinite(px) && std::isfinite(py);
}

bool CameraProjector::point(const Vec3& p, float& px, float& py) const {
    return camera_space(transform_point(world_to_camera_, p), px, py);
}

bool CameraProjector::direction(const Vec3& d, float& px, float& py) const {
    return camera_space(transform_vector(world_to_camera_, d), px, py);
}

}  // namespace pathfarm::coord
