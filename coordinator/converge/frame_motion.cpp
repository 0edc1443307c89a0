// Motion between frames, and the pixels beside moving instances (frame_motion.h).
#include "coordinator/converge/frame_motion.h"

#include <algorithm>

#include "common/math/transform.h"
#include "coordinator/converge/dilate.h"
#include "coordinator/converge/parallel_rows.h"

namespace pathfarm::coord {
namespace {

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

}  // namespace

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

// Both frames' near_moving masks, for reproject.
void mark_near_moving(Motion& m, std::vector<uint8_t>& tmp, std::vector<uint8_t>& now,
                      std::vector<uint8_t>& before) {
    near_moving(m.view->gbuffer, m, tmp, now);
    near_moving(m.prev->gbuffer, m, tmp, before);
    m.near_now = now.data();
    m.near_prev = before.data();
}

}  // namespace pathfarm::coord
