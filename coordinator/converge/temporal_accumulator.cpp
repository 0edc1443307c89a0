// Reprojection, validation, clamp and blend, one pixel at a time (TBB over rows).
#include "coordinator/converge/temporal_accumulator.h"

#include <algorithm>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "common/math/transform.h"
#include "coordinator/converge/frame_motion.h"
#include "coordinator/converge/history_search.h"
#include "coordinator/converge/parallel_rows.h"

namespace pathfarm::coord {
namespace {

struct Totals {
    double f = 0.0, kept = 0.0, frames = 0.0;
    Totals operator+(const Totals& o) const { return {f + o.f, kept + o.kept, frames + o.frames}; }
};

// History of a moving pixel clamped to this frame's 3x3 neighbourhood, mean +- `sigmas`
// deviations, widened by one frame's own noise (from the history's moments `mh`): a
// neighbourhood of sparse samples (mostly dark, a few bright) says little about the mean, and
// clamping to it alone darkened such scenes (a Sponza walk to 0.44 of its brightness).
// Not on the sky, whose light is exact sample by sample: what varied in a sky pixel's history
// was a silhouette's edge, no noise to allow for.
Rgb clamp_history(const Rgb& history, const NeighbourhoodStats& nb, std::size_t pixel,
                  const Vec2& mh, float sigmas, bool sky) {
    const Rgb mean = nb.mean(pixel);
    const float noise = sky ? 0.0f : std::sqrt(std::max(0.0f, mh.y - mh.x * mh.x));
    const Rgb bound = sigmas * (nb.sigma(pixel) + Rgb(noise));
    return glm::clamp(history, mean - bound, mean + bound);
}

// Where pixel (x, y)'s surface was last frame, and whether the history pixel there saw it.
// A pixel next to a moving instance, now or in the history, counts as moving (near_moving).
// Otherwise a wall or sky pixel at a moving figure's silhouette kept the figure's edge samples
// as a running mean (f = 1/k) after it had walked away: a ghost outline.
struct Reprojection {
    bool valid = false;
    int hx = 0, hy = 0;  // the history pixel
    bool object_moves = false;
    bool deforms = false;    // its own instance deformed this frame (object_moves too)
    bool glossy = false;     // its surface is glossy (GBuffer::glossy)
    Vec2 source{kNoSource};  // where the surface was in the last frame's pixels, if on screen
};

// The floor on f where the camera or the object moved (ConvergeOptions).
float least_blend(const Reprojection& r, const ConvergeOptions& o) {
    return r.deforms        ? o.deformed_floor
           : r.object_moves ? o.object_floor
           : r.glossy       ? std::max(o.glossy_floor, o.camera_floor)
                            : o.camera_floor;
}

// A row's G-buffer points projected into the last frame's camera at once
// (CameraProjector::points), for the pixels whose surface did not move itself; empty while the
// camera has not moved.
struct RowProjection {
    std::vector<float> x, y, z, px, py, distance;
    std::vector<int32_t> on;

    void project(const CameraProjector& project_prev, const Vec3* points, int n) {
        for (auto* plane : {&x, &y, &z, &px, &py, &distance})
            plane->resize(std::size_t(n));
        on.resize(std::size_t(n));
        for (int k = 0; k < n; ++k)  // as planes: the projection's loop vectorises in full
            x[std::size_t(k)] = points[k].x, y[std::size_t(k)] = points[k].y,
            z[std::size_t(k)] = points[k].z;
        project_prev.points(x.data(), y.data(), z.data(), n, px.data(), py.data(), on.data(),
                            distance.data());
    }
};

Reprojection reproject(const Motion& m, const CameraProjector& project_prev,
                       const CameraRays& camera_ray, const FrameView& prev, const FrameView& view,
                       const RowProjection& row, float depth_tolerance, int x, int y) {
    const GBuffer& g = view.gbuffer;
    const int w = g.width, h = g.height;
    const std::size_t i = std::size_t(y) * w + x;
    const uint32_t inst = g.instance[i];
    const uint8_t flags = inst == GBuffer::kNoInstance ? 0 : m.flags_of(inst);
    Reprojection r;
    r.object_moves = (flags & Motion::kMoving) || (m.near_now && m.near_now[i]);
    r.deforms = (flags & Motion::kDeformed) != 0;
    r.glossy = !g.glossy.empty() && g.glossy[i] != 0;
    float px = x + 0.5f, py = y + 0.5f;
    bool on_screen = true;
    float expected = g.distance[i];
    if (m.camera_moved || r.object_moves) {
        if (inst == GBuffer::kNoInstance) {  // the sky: by direction
            on_screen = project_prev.direction(camera_ray(x + 0.5f, y + 0.5f).d, px, py);
        } else {
            Vec3 p = g.position[i];
            bool known = true, still = false;
            if (flags & Motion::kDeformed) {  // by the motion of its triangle's vertices
                const Deformation* d = m.deformation_of(inst);
                Vec3 moved(0.0f);
                known = d && d->displacement(g.primitive[i], g.barycentric[i], moved);
                p += moved;
            } else if (const Mat4* to_previous = m.motion_of(inst)) {
                p = transform_point(*to_previous, p);
            } else {
                still = true;  // where it is now: the row's projection has it
            }
            if (still && !row.on.empty()) {  // projected (the camera moved)
                on_screen = (flags & Motion::kInPrevious) && row.on[std::size_t(x)];
                if (on_screen) px = row.px[std::size_t(x)], py = row.py[std::size_t(x)];
                expected = row.distance[std::size_t(x)];
            } else {
                on_screen = known && (flags & Motion::kInPrevious) && project_prev.point(p, px, py);
                expected = glm::length(p - project_prev.eye());
            }
        }
    }
    r.hx = int(std::floor(px));
    r.hy = int(std::floor(py));
    if (!on_screen || r.hx < 0 || r.hy < 0 || r.hx >= w || r.hy >= h) return r;
    r.source = Vec2(px, py);
    const std::size_t j = std::size_t(r.hy) * w + r.hx;
    if (m.near_prev && m.near_prev[j]) r.object_moves = true;  // clamped and floored
    if (!m.camera_moved && !r.object_moves) {
        // The same pixel footprint over still surfaces: its history holds whichever of them
        // the G-buffer names (it changes at edges when workload scaling changes the render
        // size it is upscaled from), unless something that has moved since covered it.
        const uint32_t was = prev.gbuffer.instance[j];
        const uint8_t was_flags = was == GBuffer::kNoInstance ? 0 : m.flags_of(was);
        r.valid = was == GBuffer::kNoInstance ||
                  (!(was_flags & Motion::kMoving) && (was_flags & Motion::kInView));
        return r;
    }
    r.valid = same_surface(prev.gbuffer, j, inst, expected, depth_tolerance) ||
              search_footprint(prev.gbuffer, (flags & Motion::kMoving) ? nullptr : m.near_prev,
                               inst, expected, depth_tolerance, px, py, r.hx, r.hy);
    return r;
}

}  // namespace

float TemporalAccumulator::min_history_frames() const {
    return frames_.empty() ? 0.0f : *std::min_element(frames_.begin(), frames_.end());
}

void TemporalAccumulator::reset() {
    previous_.reset();
    last_surfaces_.clear();
    history_ = FloatImage();
    frames_.clear();
    moments_.clear();
    sources_.clear();
}

void TemporalAccumulator::start_over(const FloatImage& image, FrameView view) {
    const std::size_t n = std::size_t(image.width) * std::size_t(image.height);
    history_ = image;
    frames_.assign(n, 1.0f);
    if (view.sample_weights.size() == n) frames_ = view.sample_weights;
    moments_.resize(n);
    sources_.assign(n, Vec2(kNoSource));
    for (std::size_t i = 0; i < n; ++i) {
        const float l =
            luminance(Rgb(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]));
        moments_[i] = Vec2(l, l * l);
    }
    remember_surfaces(view);
    replace_previous(std::move(view));
}

void TemporalAccumulator::remember_surfaces(const FrameView& view) {
    for (const auto& [id, surface] : view.surfaces)
        last_surfaces_[id] = surface;
    std::erase_if(last_surfaces_,
                  [&](const auto& entry) { return !view.instances.count(entry.first); });
}

// Every pixel of these is written by blend(); kept from frame to frame (spares allocations).
void TemporalAccumulator::size_outputs(int w, int h) {
    const std::size_t n = std::size_t(w) * std::size_t(h);
    if (next_history_.width != w || next_history_.height != h) next_history_ = FloatImage(w, h);
    next_frames_.resize(n), next_moments_.resize(n), sources_.resize(n);
}

void TemporalAccumulator::replace_previous(FrameView view) {
    if (previous_) spare_gbuffer_ = std::move(previous_->gbuffer);
    previous_ = std::move(view);
}

void TemporalAccumulator::keep(FrameView view) {
    std::swap(history_, next_history_);
    std::swap(frames_, next_frames_);
    std::swap(moments_, next_moments_);
    remember_surfaces(view);
    replace_previous(std::move(view));
}

namespace {

// The view's per-pixel sample weights when it has one for each of n pixels.
const std::vector<float>* sample_weights(const FrameView& view, std::size_t n) {
    return view.sample_weights.size() == n ? &view.sample_weights : nullptr;
}

}  // namespace

ConvergeStats TemporalAccumulator::blend(FloatImage& image, FrameView view) {
    const int w = image.width, h = image.height;
    const std::size_t n = std::size_t(w) * h;
    if (view.cut || !previous_ || history_.width != w || history_.height != h ||
        view.gbuffer.width != w || view.gbuffer.height != h) {
        start_over(image, std::move(view));
        return {1.0, 0.0, 1.0};
    }
    const FrameView& prev = *previous_;
    Motion motion = motion_between(prev, view, last_surfaces_);  // camera, instances since prev
    if (!motion.moving.empty()) mark_near_moving(motion, near_tmp_, near_now_, near_prev_);
    const CameraProjector project_prev(prev.camera, w, h);
    const CameraRays camera_ray(view.camera, w, h);
    size_outputs(w, h);
    if (motion.camera_moved || !motion.moving.empty()) neighbourhood_.compute(image);
    const std::vector<float>* weights = sample_weights(view, n);
    const Totals totals = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, h), Totals{},
        [&](const tbb::blocked_range<int>& rows, Totals t) {
            RowProjection row;
            for (int y = rows.begin(); y < rows.end(); ++y) {
                if (motion.camera_moved)
                    row.project(project_prev, &view.gbuffer.position[std::size_t(y) * w], w);
                for (int x = 0; x < w; ++x) {
                    const std::size_t i = std::size_t(y) * w + x;
                    const Rgb c = image.pixel(x, y);
                    const float l = luminance(c), s = weights ? (*weights)[i] : 1.0f;
                    Vec2& m = next_moments_[i] = Vec2(l, l * l);
                    const Reprojection r = reproject(motion, project_prev, camera_ray, prev, view,
                                                     row, o_.depth_tolerance, x, y);
                    sources_[i] = r.object_moves ? Vec2(kNoSource) : r.source;
                    if (!r.valid) {  // the image keeps c
                        next_history_.set_pixel(x, y, c);
                        next_frames_[i] = s;
                        t.f += 1.0, t.frames += s;
                        continue;
                    }
                    const std::size_t j = std::size_t(r.hy) * w + r.hx;
                    Rgb history = history_.pixel(r.hx, r.hy);
                    float k = frames_[j] + s;
                    if (motion.camera_moved || r.object_moves) {
                        history = clamp_history(history, neighbourhood_, i, moments_[j],
                                                o_.clamp_sigmas, !view.gbuffer.hit(i));
                        k = std::min(k, s / least_blend(r, o_));
                    }
                    const float f = s / k;
                    const Rgb blended = history + f * (c - history);
                    next_history_.set_pixel(x, y, blended);
                    image.set_pixel(x, y, blended);  // read above, nowhere else in this loop
                    m = moments_[j] + f * (m - moments_[j]);
                    next_frames_[i] = k;
                    t.f += f, t.kept += 1.0, t.frames += k;
                }
            }
            return t;
        },
        [](const Totals& a, const Totals& b) { return a + b; });
    keep(std::move(view));
    return {totals.f / double(n), totals.kept / double(n), totals.frames / double(n)};
}

}  // namespace pathfarm::coord
