// Reprojection, validation, clamp and blend, one pixel at a time (TBB over rows).
#include "coordinator/converge/temporal_accumulator.h"

#include <algorithm>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "common/math/transform.h"
#include "coordinator/converge/dilate.h"
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

// A deformed instance's vertices last frame and now, each with its object-to-world.
struct Deformation {
    const SurfaceVertices* before = nullptr;
    const SurfaceVertices* now = nullptr;
    Mat4 before_to_world{1.0f}, now_to_world{1.0f};

    // How far the point at barycentrics b of triangle `prim` moved since last frame, in world
    // space; false unless the triangle is the same in both frames' meshes.
    bool displacement(uint32_t prim, const Vec2& b, Vec3& moved) const {
        if (prim == FirstHit::kNone || before->indices.size() != now->indices.size() ||
            std::size_t(prim) * 3 + 2 >= now->indices.size())
            return false;
        const uint32_t* tri = now->indices.data() + std::size_t(prim) * 3;
        const uint32_t* was = before->indices.data() + std::size_t(prim) * 3;
        const std::size_t n = std::min(before->positions.size(), now->positions.size());
        if (tri[0] != was[0] || tri[1] != was[1] || tri[2] != was[2] || tri[0] >= n ||
            tri[1] >= n || tri[2] >= n)
            return false;
        const auto at = [&](const SurfaceVertices& s) {
            return (1.0f - b.x - b.y) * s.positions[tri[0]] + b.x * s.positions[tri[1]] +
                   b.y * s.positions[tri[2]];
        };
        moved =
            transform_point(before_to_world, at(*before)) - transform_point(now_to_world, at(*now));
        return true;
    }
};

// How this frame's surfaces moved since the last: the camera, and each instance that moved.
// Per pixel, reprojection asks about the instance it sees; below kTableIds ids the answers sit
// in arrays indexed by id (a set or map lookup per pixel cost a third of the blend), larger
// ids (a long game's) take the trees.
struct Motion {
    enum Flag : uint8_t { kMoving = 1, kInView = 2, kInPrevious = 4, kDeformed = 8 };
    static constexpr uint32_t kTableIds = 1u << 20;
    bool camera_moved = false;
    std::set<uint32_t> moving;                     // moved, deformed or new instances
    std::map<uint32_t, Mat4> to_previous;          // this frame's world to last frame's, per mover
    std::vector<uint8_t> flags;                    // by id
    std::vector<const Mat4*> motion;               // by id: into to_previous, or null
    std::map<uint32_t, Deformation> deformations;  // deformed instances with vertices known
    std::vector<const Deformation*> deformation;   // by id: into deformations, or null
    // Per pixel, 1 within a pixel of a moving instance in this frame's G-buffer and in the
    // last's (near_moving); null when nothing moved.
    const uint8_t* near_now = nullptr;
    const uint8_t* near_prev = nullptr;
    const FrameView* prev = nullptr;
    const FrameView* view = nullptr;

    uint8_t flags_of(uint32_t id) const {
        if (id < flags.size()) return flags[id];
        if (id < kTableIds) return 0;  // in no container: the table covers every id they hold
        return uint8_t((moving.count(id) ? kMoving : 0) |
                       (view->instances.count(id) ? kInView : 0) |
                       (prev->instances.count(id) ? kInPrevious : 0) |
                       (view->deformed.count(id) ? kDeformed : 0));
    }
    const Mat4* motion_of(uint32_t id) const {
        if (id < motion.size()) return motion[id];
        if (id < kTableIds) return nullptr;
        const auto it = to_previous.find(id);
        return it == to_previous.end() ? nullptr : &it->second;
    }
    const Deformation* deformation_of(uint32_t id) const {
        if (id < deformation.size()) return deformation[id];
        if (id < kTableIds) return nullptr;
        const auto it = deformations.find(id);
        return it == deformations.end() ? nullptr : &it->second;
    }
};

// Each deformed instance whose vertices are known now and from before, with its transforms.
void add_deformations(Motion& m, const SurfaceMap& before, const FrameView& prev,
                      const FrameView& view) {
    for (const uint32_t id : view.deformed) {
        const auto was = before.find(id), is = view.surfaces.find(id);
        const auto was_at = prev.instances.find(id), is_at = view.instances.find(id);
        if (was == before.end() || is == view.surfaces.end() || was_at == prev.instances.end() ||
            is_at == view.instances.end() || !was->second || !is->second)
            continue;
        m.deformations[id] =
            Deformation{was->second.get(), is->second.get(), was_at->second, is_at->second};
    }
}

Motion motion_between(const FrameView& prev, const FrameView& view, const SurfaceMap& before) {
    Motion m;
    m.prev = &prev;
    m.view = &view;
    m.camera_moved = prev.camera.camera_to_world != view.camera.camera_to_world ||
                     prev.camera.yfov_radians != view.camera.yfov_radians;
    m.moving = view.deformed;
    for (const auto& [id, to_world] : view.instances) {
        const auto it = prev.instances.find(id);
        if (it == prev.instances.end()) {
            m.moving.insert(id);  // new this frame: nothing of it is in the history
        } else if (it->second != to_world) {
            m.to_previous[id] = it->second * glm::inverse(to_world);
            m.moving.insert(id);
        }
    }
    uint32_t ids = 0;  // one past the largest id below kTableIds
    const auto cover = [&](uint32_t id) {
        if (id < Motion::kTableIds) ids = std::max(ids, id + 1);
    };
    for (const auto& entry : view.instances)
        cover(entry.first);
    for (const auto& entry : prev.instances)
        cover(entry.first);
    for (const uint32_t id : m.moving)
        cover(id);
    m.flags.assign(ids, 0);
    m.motion.assign(ids, nullptr);
    m.deformation.assign(ids, nullptr);
    const auto mark = [&](uint32_t id, Motion::Flag f) {
        if (id < ids) m.flags[id] |= f;
    };
    for (const uint32_t id : m.moving)
        mark(id, Motion::kMoving);
    for (const uint32_t id : view.deformed)
        mark(id, Motion::kDeformed);
    for (const auto& entry : view.instances)
        mark(entry.first, Motion::kInView);
    for (const auto& entry : prev.instances)
        mark(entry.first, Motion::kInPrevious);
    for (const auto& [id, to_prev] : m.to_previous)
        if (id < ids) m.motion[id] = &to_prev;
    add_deformations(m, before, prev, view);
    for (const auto& [id, d] : m.deformations)
        if (id < ids) m.deformation[id] = &d;
    return m;
}

// Pixels of `g` within one pixel of a moving instance: their jittered samples may have seen
// it, so their light moves with it even where their centre ray meets a still surface or the
// sky. A 3x3 dilation, rows then columns.
void near_moving(const GBuffer& g, const Motion& m, std::vector<uint8_t>& tmp,
                 std::vector<uint8_t>& out) {
    const int w = g.width, h = g.height;
    tmp.resize(g.instance.size());
    out.resize(g.instance.size());
    const auto moving = [&](std::size_t i) {
        const uint32_t id = g.instance[i];
        return uint8_t(id != GBuffer::kNoInstance && (m.flags_of(id) & Motion::kMoving));
    };
    parallel_rows(h, [&](int y) {  // the moving pixels, dilated along the row
        const std::size_t row = std::size_t(y) * w;
        for (int x = 0; x < w; ++x)
            out[row + x] = moving(row + x);
        dilate_row(&out[row], &tmp[row], w);
    });
    parallel_rows(h, [&](int y) {  // then along the column
        const uint8_t* up = &tmp[std::size_t(std::max(0, y - 1)) * w];
        const uint8_t* mid = &tmp[std::size_t(y) * w];
        const uint8_t* down = &tmp[std::size_t(std::min(h - 1, y + 1)) * w];
        uint8_t* o = &out[std::size_t(y) * w];
        for (int x = 0; x < w; ++x)
            o[x] = up[x] | mid[x] | down[x];
    });
}

// Both frames' near_moving masks, for reproject.
void mark_near_moving(Motion& m, std::vector<uint8_t>& tmp, std::vector<uint8_t>& now,
                      std::vector<uint8_t>& before) {
    near_moving(m.view->gbuffer, m, tmp, now);
    near_moving(m.prev->gbuffer, m, tmp, before);
    m.near_now = now.data();
    m.near_prev = before.data();
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

Reprojection reproject(const Motion& m, const CameraProjector& project_prev,
                       const CameraRays& camera_ray, const FrameView& prev, const FrameView& view,
                       float depth_tolerance, int x, int y) {
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
            bool known = true;
            if (flags & Motion::kDeformed) {  // by the motion of its triangle's vertices
                const Deformation* d = m.deformation_of(inst);
                Vec3 moved(0.0f);
                known = d && d->displacement(g.primitive[i], g.barycentric[i], moved);
                p += moved;
            } else if (const Mat4* to_previous = m.motion_of(inst)) {
                p = transform_point(*to_previous, p);
            }
            on_screen = known && (flags & Motion::kInPrevious) && project_prev.point(p, px, py);
            expected = glm::length(p - project_prev.eye());
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
    previous_ = std::move(view);
}

void TemporalAccumulator::remember_surfaces(const FrameView& view) {
    for (const auto& [id, surface] : view.surfaces)
        last_surfaces_[id] = surface;
    std::erase_if(last_surfaces_,
                  [&](const auto& entry) { return !view.instances.count(entry.first); });
}

void TemporalAccumulator::keep(FrameView view) {
    std::swap(history_, next_history_);
    std::swap(frames_, next_frames_);
    std::swap(moments_, next_moments_);
    remember_surfaces(view);
    previous_ = std::move(view);
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
    // Every pixel of these is written below, kept from frame to frame (spares allocations).
    if (next_history_.width != w || next_history_.height != h) next_history_ = FloatImage(w, h);
    next_frames_.resize(n), next_moments_.resize(n), sources_.resize(n);
    if (motion.camera_moved || !motion.moving.empty()) neighbourhood_.compute(image);
    const std::vector<float>* weights = sample_weights(view, n);
    const Totals totals = tbb::parallel_reduce(
        tbb::blocked_range<int>(0, h), Totals{},
        [&](const tbb::blocked_range<int>& rows, Totals t) {
            for (int y = rows.begin(); y < rows.end(); ++y)
                for (int x = 0; x < w; ++x) {
                    const std::size_t i = std::size_t(y) * w + x;
                    const Rgb c = image.pixel(x, y);
                    const float l = luminance(c), s = weights ? (*weights)[i] : 1.0f;
                    Vec2& m = next_moments_[i] = Vec2(l, l * l);
                    const Reprojection r = reproject(motion, project_prev, camera_ray, prev, view,
                                                     o_.depth_tolerance, x, y);
                    sources_[i] = r.object_moves ? Vec2(kNoSource) : r.source;
                    if (!r.valid) {  // the image keeps c
                        next_history_.set_pixel(x, y, c);
                        next_frames_[i] = s;
                        t.f += 1.0, t.frames += s;
                        continue;
                    }
                    Rgb history = history_.pixel(r.hx, r.hy);
                    float k = frames_[std::size_t(r.hy) * w + r.hx] + s;
                    if (motion.camera_moved || r.object_moves) {
                        history = clamp_history(history, neighbourhood_, i,
                                                moments_[std::size_t(r.hy) * w + r.hx],
                                                o_.clamp_sigmas, !view.gbuffer.hit(i));
                        k = std::min(k, s / least_blend(r, o_));
                    }
                    const float f = s / k;
                    const Rgb blended = history + f * (c - history);
                    next_history_.set_pixel(x, y, blended);
                    image.set_pixel(x, y, blended);  // read above, nowhere else in this loop
                    const Vec2 mh = moments_[std::size_t(r.hy) * w + r.hx];
                    m = mh + f * (m - mh);
                    next_frames_[i] = k;
                    t.f += f, t.kept += 1.0, t.frames += k;
                }
            return t;
        },
        [](const Totals& a, const Totals& b) { return a + b; });
    keep(std::move(view));
    return {totals.f / double(n), totals.kept / double(n), totals.frames / double(n)};
}

}  // namespace pathfarm::coord
