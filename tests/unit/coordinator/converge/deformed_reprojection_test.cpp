// Deformed surfaces (skinning, morph targets, vertex edits) reproject by the motion of their
// triangles' vertices: the frame pipeline's view carries each deformed instance's vertices, the
// tracers' first hits the triangle and barycentrics, and history follows the surface to where
// it was. The Cornell box's two blocks share one cube mesh, whose vertices are edited: both
// blocks deform, each placed by its own rotation and scale.
#include <cmath>

#include <gtest/gtest.h>

#include "common/math/transform.h"
#include "common/scene/load/builtin_scenes.h"
#include "coordinator/converge/temporal_accumulator.h"
#include "coordinator/frame/frame_pipeline.h"
#include "tests/support/gbuffer_helpers.h"

namespace pathfarm::coord::deformed_reprojection_test {
namespace {

constexpr int kSize = 64;

struct DeformingCube {
    FramePipeline pipeline{make_cornell_box(), PipelineOptions{}};
    uint32_t cube = 0;             // the blocks' shared mesh
    std::vector<uint32_t> blocks;  // its instances
    std::vector<Vec3> rest;        // its vertices before any edit

    DeformingCube() {
        const SceneState& s = pipeline.state();
        const uint32_t node = pipeline.graph().find_nodes("short-block").at(0);
        for (const auto& [id, inst] : s.instances)
            if (pipeline.graph().node_of_instance(id) == node) cube = inst.mesh;
        for (const auto& [id, inst] : s.instances)
            if (inst.mesh == cube) blocks.push_back(id);
        rest = s.meshes.at(cube).positions;
    }
    // Frame `frame` with the cube's vertices moved by `shift` (object space) from rest, if given.
    FrameView frame(uint64_t frame, std::optional<Vec3> shift) {
        if (shift) {
            std::vector<Vec3> moved = rest;
            for (Vec3& p : moved)
                p += *shift;
            EXPECT_TRUE(pipeline.graph().edit_vertices(cube, 0, moved).ok());
        }
        const FrameUpdate u = pipeline.advance(frame, double(frame) / 30.0, {});
        FrameView v = pipeline.view(u);
        v.gbuffer =
            test::first_hit_gbuffer(pipeline.state(), v.camera, uint32_t(frame), kSize, kSize);
        return v;
    }
    bool on_block(const FrameView& v, std::size_t i) const {
        return std::find(blocks.begin(), blocks.end(), v.gbuffer.instance[i]) != blocks.end();
    }
};

// Each pixel's centre in pixels, in the red and green channels.
FloatImage pixel_coordinates() {
    FloatImage img(kSize, kSize);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            img.set_pixel(x, y, Rgb(x + 0.5f, y + 0.5f, 1.0f));
    return img;
}

// With the clamp off (its bound scales the new frame's local deviation, so that frame must
// vary) and half of each blended pixel from history, blending the pixels' negated coordinates
// shows where each pixel's history came from: twice the result plus the pixel's own centre is
// that history pixel's centre.
TEST(DeformedReprojection, HistoryComesFromWhereTheTriangleWas) {
    DeformingCube scene;
    ASSERT_EQ(scene.blocks.size(), 2u);
    ConvergeOptions o;
    o.clamp_sigmas = 1e9f;
    o.deformed_floor = 0.5f;  // the blocks deform: their floor
    TemporalAccumulator acc(o);
    FloatImage img = pixel_coordinates();
    acc.blend(img, scene.frame(0, std::nullopt));
    // The first edit: the accumulator has not seen the cube's vertices yet, so the blocks keep
    // no history (it learns them now).
    img = pixel_coordinates();
    const FrameView v1 = scene.frame(1, Vec3(0.1f, 0.0f, 0.0f));
    ASSERT_EQ(v1.deformed.size(), 2u);
    ASSERT_EQ(v1.surfaces.size(), 2u);
    acc.blend(img, v1);
    for (std::size_t i = 0; i < img.rgb.size() / 3; ++i)
        if (scene.on_block(v1, i)) {
            EXPECT_EQ(acc.history_frames()[i], 1.0f) << "pixel " << i;
        }

    // The second: the cube slides 0.3 of its size (about 3-4 pixels) along its own x.
    const Vec3 shift(0.4f, 0.0f, 0.0f);
    const FrameView v2 = scene.frame(2, shift);
    img = pixel_coordinates();
    for (float& c : img.rgb)
        c = -c;
    acc.blend(img, v2);
    const CameraProjector project(v1.camera, kSize, kSize);
    int block = 0, kept = 0, exact = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const std::size_t i = std::size_t(y) * kSize + x;
            if (!scene.on_block(v2, i)) continue;
            ++block;
            if (acc.history_frames()[i] < 2.0f) continue;
            ++kept;
            // Where the surface point was: moved back by the edit's step, placed by its block.
            const Mat4& to_world = v2.instances.at(v2.gbuffer.instance[i]);
            const Vec3 step = transform_point(to_world, shift - Vec3(0.1f, 0.0f, 0.0f)) -
                              transform_point(to_world, Vec3(0.0f));
            float px = 0.0f, py = 0.0f;
            ASSERT_TRUE(project.point(v2.gbuffer.position[i] - step, px, py));
            const Rgb from = 2.0f * img.pixel(x, y) + Rgb(x + 0.5f, y + 0.5f, 0.0f);
            EXPECT_LE(std::abs(from.x - (std::floor(px) + 0.5f)), 1.0f)
                << x << "," << y << " from " << from.x << "," << from.y << " want " << px << ","
                << py;
            EXPECT_LE(std::abs(from.y - (std::floor(py) + 0.5f)), 1.0f) << x << "," << y;
            exact += from.x == std::floor(px) + 0.5f && from.y == std::floor(py) + 0.5f;
            EXPECT_GT(std::abs(from.x - (x + 0.5f)) + std::abs(from.y - (y + 0.5f)), 1.5f)
                << "the block moved several pixels: its history is not the pixel's own";
        }
    EXPECT_GT(block, 200);
    EXPECT_GT(kept, block * 3 / 4) << "most of the blocks stayed in view of themselves";
    EXPECT_GT(exact, kept * 9 / 10);
}

// A deforming surface's light changes as it deforms (its normals turn), and on the denoise
// bench's Cesium Man a history floored as a rigid mover's (0.3) lagged: its pixels keep at
// most 1 / deformed_floor frames, fewer than a rigid mover's 1 / object_floor, and most of
// them reach it when the deformation is slow enough to keep history at all.
TEST(DeformedReprojection, DeformingSurfacesKeepAtMostTheirFloorsHistory) {
    const ConvergeOptions o;
    ASSERT_GT(o.deformed_floor, o.object_floor);
    DeformingCube scene;
    TemporalAccumulator acc(o);
    FloatImage img(kSize, kSize);
    acc.blend(img, scene.frame(0, std::nullopt));
    int block = 0, floored = 0;
    for (int k = 1; k <= 8; ++k) {
        img = FloatImage(kSize, kSize);
        const FrameView v = scene.frame(uint64_t(k), Vec3(0.02f * float(k), 0.0f, 0.0f));
        acc.blend(img, v);
        if (k < 8) continue;
        for (std::size_t i = 0; i < img.rgb.size() / 3; ++i) {
            if (!scene.on_block(v, i)) continue;
            ++block;
            const float frames = acc.history_frames()[i];
            EXPECT_LE(frames, 1.0f / o.deformed_floor + 1e-3f) << "pixel " << i;
            floored += frames > 1.0f / o.deformed_floor - 1e-3f;
        }
    }
    EXPECT_GT(block, 200);
    EXPECT_GT(floored, block / 2);
}

// A deformed instance whose vertices the view does not carry keeps no history, and neither
// does one whose vertices last frame were not what that frame's view said (the depth check).
TEST(DeformedReprojection, UnknownOrWrongMotionKeepsNoHistory) {
    for (const bool drop : {true, false}) {
        DeformingCube scene;
        TemporalAccumulator acc;
        FloatImage img(kSize, kSize);
        acc.blend(img, scene.frame(0, std::nullopt));
        FrameView v1 = scene.frame(1, Vec3(0.1f, 0.0f, 0.0f));
        if (!drop) {  // claims the cube sat far off towards the camera
            auto claimed = std::make_shared<SurfaceVertices>(*v1.surfaces.begin()->second);
            for (Vec3& p : claimed->positions)
                p += Vec3(0.0f, 0.0f, -1.5f);
            for (auto& entry : v1.surfaces)
                entry.second = claimed;
        }
        acc.blend(img, v1);
        FrameView v2 = scene.frame(2, Vec3(0.4f, 0.0f, 0.0f));
        if (drop) v2.surfaces.clear();
        acc.blend(img, v2);
        int block = 0, kept = 0;
        for (std::size_t i = 0; i < img.rgb.size() / 3; ++i)
            if (scene.on_block(v2, i)) ++block, kept += acc.history_frames()[i] > 1.0f;
        EXPECT_GT(block, 200);
        EXPECT_LT(kept, block / 20) << (drop ? "no vertices" : "wrong vertices");
    }
}

}  // namespace
}  // namespace pathfarm::coord::deformed_reprojection_test
