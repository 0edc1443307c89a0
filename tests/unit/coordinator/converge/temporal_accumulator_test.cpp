// Converging on real renders of builtin:cornell (Embree backend, one sample per pixel per
// frame) against a converged reference: a still view's error falls as 1/sqrt(k); after a
// camera move, reprojected history beats a reset where it is valid and is dropped where it
// is not. Object motion: what a moving ball uncovers starts over. The G-buffer the farm makes
// from the tracers' first hits matches one traced through pixel centres by the coordinator's
// BVH, which the accumulator tests use as their exact G-buffer.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "common/film/image_compare.h"
#include "common/math/transform.h"
#include "common/sampling/rng.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/scene_state.h"
#include "coordinator/accel/accel_updater.h"
#include "coordinator/converge/temporal_accumulator.h"
#include "coordinator/query/ray_query.h"
#include "coordinator/scene_graph/scene_graph.h"
#include "tests/support/gbuffer_helpers.h"
#include "tests/support/render_helpers.h"

namespace pathfarm::coord::temporal_accumulator_test {
namespace {

using test::first_hit_gbuffer;

Vec3 camera_eye(const Camera& c) { return transform_point(c.camera_to_world, Vec3(0.0f)); }

constexpr int kSize = 48;

// One ray through each pixel centre against the coordinator's BVH: the exact G-buffer.
GBuffer trace_gbuffer(const AccelSnapshot& accel, const Camera& camera, int width, int height) {
    GBuffer g;
    g.resize(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const Ray ray = generate_camera_ray(camera, width, height, x + 0.5f, y + 0.5f);
            const std::size_t i = std::size_t(y) * width + x;
            if (const auto hit = closest_hit(accel, ray)) {
                g.distance[i] = hit->distance;
                g.instance[i] = hit->instance;
                g.position[i] = hit->point;
            }
        }
    return g;
}

struct Shot {
    SceneModel scene;
    std::shared_ptr<const AccelSnapshot> accel;
    FrameView view;
};

// The scene as the coordinator sees it (G-buffer from its own BVH) with camera `camera`.
Shot shoot(const Camera& camera) {
    Shot s;
    s.scene = make_cornell_box();
    s.scene.cameras.at(0).camera_to_world = camera.camera_to_world;
    SceneGraph graph(s.scene);
    AccelUpdater accel;
    s.accel = accel.build(graph.state(), 0);
    s.view.camera = s.scene.cameras.at(0);
    for (const InstanceAccel& i : s.accel->instances)
        s.view.instances[i.id] = i.to_world;
    s.view.gbuffer = trace_gbuffer(*s.accel, s.view.camera, kSize, kSize);
    return s;
}

FloatImage frame(const Shot& s, uint32_t k, int spp = 1) {
    test::RenderRequest r;
    r.width = r.height = kSize;
    r.spp = spp;
    r.frame = k;
    r.seed = 7;
    return test::render(s.scene, r);
}

Camera cornell_camera() { return make_cornell_box().cameras.at(0); }

Camera panned(float degrees) {
    Camera c = cornell_camera();
    c.camera_to_world =
        c.camera_to_world * glm::rotate(Mat4(1.0f), glm::radians(degrees), Vec3(0, 1, 0));
    return c;
}

TEST(TemporalAccumulator, StillViewConvergesAsOneOverSqrtK) {
    const Shot s = shoot(cornell_camera());
    const FloatImage reference = frame(s, 100000, 2048);
    TemporalAccumulator acc;
    std::vector<std::pair<int, double>> errors;
    for (int k = 1; k <= 64; ++k) {
        FloatImage img = frame(s, uint32_t(k));
        const ConvergeStats st = acc.blend(img, s.view);
        EXPECT_NEAR(st.mean_f, 1.0 / k, 1e-6) << "a still frame is a true running mean";
        if (k == 1 || k == 4 || k == 16 || k == 64) errors.emplace_back(k, rmse(img, reference));
    }
    // Least-squares slope of log RMSE against log k: -0.5 for 1/sqrt(k).
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (auto [k, e] : errors) {
        const double x = std::log(double(k)), y = std::log(e);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const double n = double(errors.size());
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    EXPECT_NEAR(slope, -0.5, 0.1) << "RMSE at k=1: " << errors[0].second
                                  << ", k=64: " << errors[3].second;
}

// With the exact G-buffer, and with the farm's: each frame's from its jittered first hits.
class CameraMove : public ::testing::TestWithParam<bool> {};

TEST_P(CameraMove, KeepsValidHistoryAndDropsTheRest) {
    const bool first_hits = GetParam();
    Shot before = shoot(cornell_camera());
    Shot after = shoot(panned(4.0f));
    const auto view_of = [&](Shot& s, uint32_t k) -> const FrameView& {
        if (first_hits) s.view.gbuffer = first_hit_gbuffer(s.scene, s.view.camera, k, kSize, kSize);
        return s.view;
    };
    const FloatImage reference = frame(after, 100000, 2048);
    TemporalAccumulator kept;
    for (int k = 1; k <= 32; ++k) {
        FloatImage img = frame(before, uint32_t(k));
        const ConvergeStats st = kept.blend(img, view_of(before, uint32_t(k)));
        if (k > 1) {
            EXPECT_EQ(st.kept, 1.0) << "a still view keeps every pixel, frame " << k;
        }
    }
    double kept_error = 0.0, reset_error = 0.0;
    TemporalAccumulator fresh;
    for (int k = 33; k <= 36; ++k) {
        FloatImage a = frame(after, uint32_t(k)), b = a;
        const ConvergeStats st = kept.blend(a, view_of(after, uint32_t(k)));
        fresh.blend(b, after.view);
        if (k == 33) {  // the frame of the move
            EXPECT_GT(st.kept, 0.7) << "most of the view survives a 4 degree pan";
            EXPECT_LT(st.kept, 0.99) << "the columns panned into view have no history";
            // Panning left brings new columns in on the left: they start over.
            const auto& frames = kept.history_frames();
            for (int y = 0; y < kSize; ++y)
                EXPECT_EQ(frames[std::size_t(y) * kSize], 1.0f) << "row " << y;
            // Kept history is capped by the camera-motion floor.
            for (float f : frames)
                EXPECT_LE(f, 1.0f / ConvergeOptions{}.camera_floor + 1e-3f);
        }
        kept_error = rmse(a, reference);
        reset_error = rmse(b, reference);
    }
    EXPECT_LT(kept_error, 0.75 * reset_error);
}

INSTANTIATE_TEST_SUITE_P(GBuffers, CameraMove, ::testing::Values(false, true),
                         [](const auto& param_info) {
                             return param_info.param ? "FirstHits" : "Exact";
                         });

// A still view whose render size workload scaling changes: the upscaled G-buffer differs at
// edges from frame to frame, yet every pixel keeps its history (the same footprint over still
// surfaces), and keeps converging.
TEST(TemporalAccumulator, AStillViewKeepsItsHistoryWhenTheRenderSizeChanges) {
    const Shot s = shoot(cornell_camera());
    TemporalAccumulator acc;
    FrameView view = s.view;
    for (int k = 1; k <= 8; ++k) {
        const float scale = k % 3 == 0 ? 0.5f : k % 3 == 1 ? 1.0f : 0.75f;
        view.gbuffer = first_hit_gbuffer(s.scene, s.view.camera, uint32_t(k), kSize, kSize, scale);
        FloatImage img = frame(s, uint32_t(k));
        const ConvergeStats st = acc.blend(img, view);
        if (k > 1) {
            EXPECT_EQ(st.kept, 1.0) << "frame " << k;
        }
    }
    EXPECT_EQ(acc.min_history_frames(), 8.0f);
}

// builtin:default seen from its camera before and after its gold ball moves 0.4 m along x.
struct MovingBall {
    FrameView before, after;
    uint32_t ball = 0;  // its instance id
};

MovingBall moving_ball_views(int w, int h) {
    SceneModel scene = make_default_scene();
    SceneGraph graph(scene);
    AccelUpdater accel;
    const auto snapshot0 = accel.build(graph.state(), 0);
    const uint32_t ball = graph.find_nodes("gold-ball").at(0);
    MovingBall m;
    FrameView& v0 = m.before;
    v0.camera = graph.state().cameras.at(graph.state().active_camera);
    for (const InstanceAccel& i : snapshot0->instances)
        v0.instances[i.id] = i.to_world;
    v0.gbuffer = trace_gbuffer(*snapshot0, v0.camera, w, h);
    EXPECT_TRUE(
        graph.set_node_transform(ball, glm::translate(Mat4(1.0f), Vec3(1.0f, 0.35f, -4.2f))));
    const ChangeSet changes = graph.take_changes();
    const auto snapshot1 = accel.update(graph.state(), changes, 1);
    FrameView& v1 = m.after;
    v1 = v0;
    v1.instances.clear();
    for (const InstanceAccel& i : snapshot1->instances)
        v1.instances[i.id] = i.to_world;
    v1.gbuffer = trace_gbuffer(*snapshot1, v1.camera, w, h);
    for (const auto& [id, inst] : graph.state().instances)
        if (graph.node_of_instance(id) == ball) m.ball = id;
    return m;
}

// Whether `instance` is within one pixel of pixel i in `v`'s G-buffer.
bool next_to(const FrameView& v, uint32_t instance, std::size_t i, int w, int h) {
    const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx >= 0 && ny >= 0 && nx < w && ny < h &&
                v.gbuffer.instance[std::size_t(ny) * w + nx] == instance)
                return true;
        }
    return false;
}

TEST(TemporalAccumulator, WhatAMovingObjectUncoversStartsOver) {
    const int w = 96, h = 54;
    const MovingBall m = moving_ball_views(w, h);
    const FrameView &v0 = m.before, &v1 = m.after;
    const uint32_t ball_instance = m.ball;
    TemporalAccumulator acc;
    FloatImage flat(w, h);
    for (int k = 0; k < 8; ++k) {
        FloatImage img = flat;
        acc.blend(img, v0);
    }
    FloatImage img = flat;
    acc.blend(img, v1);
    int uncovered = 0, ball_pixels = 0, beside = 0;
    for (std::size_t i = 0; i < std::size_t(w) * h; ++i) {
        const bool was_ball = v0.gbuffer.instance[i] == ball_instance;
        const bool is_ball = v1.gbuffer.instance[i] == ball_instance;
        // The temporal anti-aliasing's motion (sources): none on and beside the ball, where
        // it would carry the ball's light into the wall it left (temporal_aa.h).
        const Vec2 source = acc.sources()[i];
        if (was_ball && !is_ball) {
            ++uncovered;
            EXPECT_EQ(acc.history_frames()[i], 1.0f) << "uncovered pixel " << i;
        }
        if (is_ball) {
            ++ball_pixels;
            EXPECT_LE(acc.history_frames()[i], 1.0f / ConvergeOptions{}.object_floor + 1e-3f);
            EXPECT_EQ(source.x, kNoSource) << "ball pixel " << i;
        }
        if (!was_ball && !is_ball && v0.gbuffer.instance[i] == v1.gbuffer.instance[i]) {
            if (next_to(v0, ball_instance, i, w, h) || next_to(v1, ball_instance, i, w, h)) {
                ++beside;  // its samples may have seen the ball: it moves with it
                EXPECT_LE(acc.history_frames()[i], 1.0f / ConvergeOptions{}.object_floor + 1e-3f);
                EXPECT_EQ(source.x, kNoSource) << "pixel beside the ball " << i;
            } else {
                EXPECT_EQ(acc.history_frames()[i], 9.0f) << "still surface " << i;
                EXPECT_EQ(source, Vec2(float(i % w) + 0.5f, float(i / w) + 0.5f)) << i;
            }
        }
    }
    EXPECT_GT(uncovered, 10);
    EXPECT_GT(ball_pixels, 10);
    EXPECT_GT(beside, 10);
}

// The ball's silhouette as its edge pixels' samples see it: bright on the ball and on every
// pixel next to it, for 8 still frames; then the ball moves and the frame is dark. The pixels
// beside where it was show the wall again: their history is clamped to the dark frame, not
// kept as a running mean that would leave a ghost outline at 8/9 of its brightness.
TEST(TemporalAccumulator, AMovingObjectLeavesNoGhostOutline) {
    const int w = 96, h = 54;
    const MovingBall m = moving_ball_views(w, h);
    FloatImage lit(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (next_to(m.before, m.ball, std::size_t(y) * w + x, w, h))
                lit.set_pixel(x, y, Rgb(10.0f));
    TemporalAccumulator acc;
    for (int k = 0; k < 8; ++k) {
        FloatImage img = lit;
        acc.blend(img, m.before);
    }
    FloatImage img(w, h);
    acc.blend(img, m.after);
    int outline = 0;
    for (std::size_t i = 0; i < std::size_t(w) * h; ++i) {
        const bool was_beside =
            next_to(m.before, m.ball, i, w, h) && m.before.gbuffer.instance[i] != m.ball;
        if (!was_beside || next_to(m.after, m.ball, i, w, h)) continue;
        ++outline;
        EXPECT_LT(img.rgb[3 * i], 1.0f) << "pixel " << i << " kept the ball's edge light";
    }
    EXPECT_GT(outline, 10);
}

// Reprojection looks instance ids up in tables below 2^20 and in the views' maps above: a long
// game's large ids get the same history, bit for bit, as small ones, on a moving object and a
// moving camera.
FrameView shift_ids(FrameView v, uint32_t by) {
    std::map<uint32_t, Mat4> instances;
    for (const auto& [id, to_world] : v.instances)
        instances[id + by] = to_world;
    v.instances = std::move(instances);
    for (uint32_t& id : v.gbuffer.instance)
        if (id != GBuffer::kNoInstance) id += by;
    return v;
}

TEST(TemporalAccumulator, LargeInstanceIdsReprojectLikeSmallOnes) {
    const int w = 64, h = 36;
    MovingBall m = moving_ball_views(w, h);
    FrameView turned = m.after;
    turned.camera.camera_to_world =
        glm::rotate(turned.camera.camera_to_world, glm::radians(1.0f), Vec3(0.0f, 1.0f, 0.0f));
    // The same surfaces (G-buffer) seen from a slightly turned camera: every pixel reprojects.
    for (const uint32_t by : {0u, (1u << 20) - 3u, 1u << 24}) {
        TemporalAccumulator small, large;
        Pcg32 rng(5);
        for (const FrameView* v : {&m.before, &m.before, &m.before, &m.after, &turned}) {
            FloatImage noise(w, h);
            for (float& c : noise.rgb)
                c = rng.next_float();
            FloatImage a = noise, b = noise;
            small.blend(a, *v);
            large.blend(b, shift_ids(*v, by));
            ASSERT_EQ(a.rgb, b.rgb) << "ids shifted by " << by;
            ASSERT_EQ(small.history_frames(), large.history_frames()) << "ids shifted by " << by;
        }
        EXPECT_LT(*std::min_element(small.history_frames().begin(), small.history_frames().end()),
                  4.0f);  // the ball and the turn dropped some history
    }
}

// builtin:default as a tracer renders it from the coordinator's scene graph (the replica's
// model, camera-relative): the G-buffer made from its first hits is the one the coordinator
// traced through pixel centres itself, up to float against double precision; except where
// the centre ray meets the mirror or the glass sphere, whose first hits show what lies beyond
// them (tests/render/first_hits_test.cpp checks those).
TEST(GBuffer, FromTracerFirstHitsMatchesACentreTrace) {
    SceneGraph graph(make_default_scene());
    AccelUpdater accel;
    const auto snapshot = accel.build(graph.state(), 0);
    const Camera camera = graph.state().cameras.at(graph.state().active_camera);
    const int w = 96, h = 54;
    const GBuffer got = first_hit_gbuffer(make_default_scene(), camera, 4, w, h);
    const GBuffer want = trace_gbuffer(*snapshot, camera, w, h);
    std::set<uint32_t> see_through;  // the mirror's and the glass sphere's ids
    const SceneModel model = to_scene_model(graph.state());
    for (const Instance& inst : model.instances) {
        const Material& m =
            model.materials[std::size_t(model.meshes[std::size_t(inst.mesh)].material)];
        if (m.transmission_factor > 0.0f ||
            (m.metallic_factor >= 0.5f && m.roughness_factor == 0.0f))
            see_through.insert(inst.id);
    }
    ASSERT_EQ(see_through.size(), 2u);
    int same = 0, close = 0, beyond = 0;
    for (std::size_t i = 0; i < got.instance.size(); ++i) {
        if (want.hit(i) && see_through.count(want.instance[i])) {
            ++beyond;
            continue;
        }
        if (got.instance[i] != want.instance[i]) continue;
        ++same;
        if (!want.hit(i)) {
            ++close;
            continue;
        }
        const float rel = std::abs(got.distance[i] - want.distance[i]) / want.distance[i];
        if (rel < 0.03f &&
            glm::length(got.position[i] - want.position[i]) < 0.03f * want.distance[i])
            ++close;
        EXPECT_NEAR(glm::length(got.normal[i]), 1.0f, 1e-3f);
    }
    EXPECT_GT(beyond, 50);
    EXPECT_GE(same, (w * h - beyond) * 995 / 1000);
    EXPECT_EQ(close, same);
    // Upscaled (workload scaling rendered at half size): the nearest render pixel's hit.
    const GBuffer upscaled = gbuffer_from_first_hits(
        std::vector<FirstHit>(std::size_t(w) * h, FirstHit{2.0f, 7u, Vec3(0, 1, 0), Rgb(0.5f)}), w,
        h, camera, 2 * w, 2 * h);
    EXPECT_EQ(upscaled.instance[std::size_t(2 * h - 1) * 2 * w + 5], 7u);
    EXPECT_NEAR(glm::length(upscaled.position[5] - camera_eye(camera)), 2.0f, 1e-5f);
}

TEST(TemporalAccumulator, ACutStartsEveryPixelOver) {
    const Shot s = shoot(cornell_camera());
    TemporalAccumulator acc;
    for (int k = 1; k <= 4; ++k) {
        FloatImage img = frame(s, uint32_t(k));
        acc.blend(img, s.view);
    }
    FrameView cut = s.view;
    cut.cut = true;
    FloatImage img = frame(s, 5);
    const FloatImage raw = img;
    EXPECT_EQ(acc.blend(img, cut).mean_f, 1.0);
    EXPECT_EQ(img.rgb, raw.rgb);
}

}  // namespace
}  // namespace pathfarm::coord::temporal_accumulator_test
