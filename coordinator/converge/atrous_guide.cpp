// The wavelet's guide (AtrousFilter::set_guide): the G-buffer's normals rotated into camera
// space, depths along the view axis and the centre values of the tangent-plane test, written
// into the padded planes the row passes read, eight pixels at a time.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "coordinator/converge/atrous.h"
#include "coordinator/converge/parallel_rows.h"
#include "coordinator/converge/vector_lanes.h"

namespace pathfarm::coord {

using namespace lanes;

namespace {

// Eight pixels' guide inputs: the normal (x, y, z), the film point's x, the distance, and
// whether the filter runs there (-1) or not (0).
struct GuideLanes {
    vf8 x, y, z, fx, distance;
    vi8 on;
};

// Eight whole pixels from interleaved normals and the row's planes.
[[gnu::always_inline]] inline GuideLanes guide_lanes(const float* n, const float* fx,
                                                     const float* distance, const uint8_t* f) {
    GuideLanes l;
    l.x = vf8{n[0], n[3], n[6], n[9], n[12], n[15], n[18], n[21]};
    l.y = vf8{n[1], n[4], n[7], n[10], n[13], n[16], n[19], n[22]};
    l.z = vf8{n[2], n[5], n[8], n[11], n[14], n[17], n[20], n[23]};
    l.fx = load<vf8>(fx);
    l.distance = load<vf8>(distance);
    const vi8 bytes{f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7]};
    l.on = bytes != 0;
    return l;
}

// The row's last `count` (< 8) pixels; the other lanes zero.
GuideLanes guide_lanes_tail(const GBuffer& g, const std::vector<float>& film_x,
                            const std::vector<uint8_t>& filter, std::size_t i, int x, int count) {
    float n[3][8] = {}, fx[8] = {}, distance[8] = {};
    int32_t keep[8] = {};
    for (int l = 0; l < count; ++l) {
        n[0][l] = g.normal[i + l].x;
        n[1][l] = g.normal[i + l].y;
        n[2][l] = g.normal[i + l].z;
        fx[l] = film_x[std::size_t(x + l)];
        distance[l] = g.distance[i + l];
        keep[l] = filter[i + l] ? -1 : 0;
    }
    GuideLanes lanes{load<vf8>(n[0]), load<vf8>(n[1]),     load<vf8>(n[2]),
                     load<vf8>(fx),   load<vf8>(distance), {}};
    std::memcpy(&lanes.on, keep, sizeof lanes.on);
    return lanes;
}

}  // namespace

void AtrousFilter::set_guide(const GBuffer& g, const Camera& camera,
                             const std::vector<uint8_t>& filter) {
    // The widest tap offset, and at least a lane's width for the rows' rounded-up ends.
    const int pad = std::max(kMaxLanes, o_.radius << (o_.levels - 1));
    if (g.width != width_ || g.height != height_ || pad != pad_) allocate(g.width, g.height, pad);
    // Camera space: normals rotated into it, points as depth along the view axis times the
    // pixel centre's film point (x, y, -1) at unit depth (generate_camera_ray's inverse).
    const Mat3 m(glm::inverse(camera.camera_to_world));  // world to camera, for normals
    const float tan_half = std::tan(0.5f * camera.yfov_radians);
    pitch_ = 2.0f * tan_half / float(height_);
    const float film_x = 2.0f * tan_half * float(width_) / float(height_) / float(width_);
    const float inv_sigma_pitch = 1.0f / (o_.sigma_plane * pitch_);
    film_x_.resize(std::size_t(width_));
    for (int x = 0; x < width_; ++x)
        film_x_[std::size_t(x)] = (float(x) + 0.5f) * film_x - 0.5f * float(width_) * film_x;
    parallel_rows(height_, [&](int y) {
        const float fy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height_)) * tan_half;
        guide_row(g, m, filter, y, fy, inv_sigma_pitch);
    });
}

void AtrousFilter::guide_row(const GBuffer& g, const Mat3& m, const std::vector<uint8_t>& filter,
                             int y, float fy, float inv_sigma_pitch) {
    const std::size_t row = std::size_t(y) * width_;
    const std::size_t k0 = std::size_t(y + pad_) * stride_ + pad_;
    // Eight pixels at a time, the pixels not filtered (zero normal, infinite distance) computed
    // too and then zeroed. The same operations in the same order as glm::normalize
    // (v * (1 / sqrt(v . v))). The lanes are built in registers: a vector loaded from eight
    // scalars just stored (the row's end, below) waits for them to reach the cache.
    for (int x = 0; x < width_; x += 8) {
        const std::size_t i = row + x, k = k0 + x;
        GuideLanes in;
        if (x + 8 <= width_)
            in = guide_lanes(&g.normal[i].x, &film_x_[std::size_t(x)], &g.distance[i], &filter[i]);
        else  // lanes past the row's end go into the padding, which stays zero
            in = guide_lanes_tail(g, film_x_, filter, i, x, width_ - x);
        const vf8 cx = m[0][0] * in.x + m[1][0] * in.y + m[2][0] * in.z;
        const vf8 cy = m[0][1] * in.x + m[1][1] * in.y + m[2][1] * in.z;
        const vf8 cz = m[0][2] * in.x + m[1][2] * in.y + m[2][2] * in.z;
        const vf8 inv_length = 1.0f / vsqrt(cx * cx + cy * cy + cz * cz);
        const vf8 nx = cx * inv_length, ny = cy * inv_length, nz = cz * inv_length;
        const vf8 z = in.distance / vsqrt(in.fx * in.fx + fy * fy + 1.0f);
        const vf8 slope = nx * in.fx + ny * fy - nz;  // n . (fx, fy, -1)
        const vi8 on = in.on;
        store(&nx_[k], on ? nx : vf8{});
        store(&ny_[k], on ? ny : vf8{});
        store(&nz_[k], on ? nz : vf8{});
        store(&z_[k], on ? z : vf8{});
        store(&slope_[k], on ? slope : vf8{});
        store(&offset_[k], on ? z * slope : vf8{});
        store(&inv_plane_[k], on ? inv_sigma_pitch / in.distance : vf8{});
    }
}

}  // namespace pathfarm::coord
