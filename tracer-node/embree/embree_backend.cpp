// EmbreeBackend: owns the Embree scene and the shading data derived from the SceneModel, and
// renders row ranges with a TBB task arena limited to the configured thread count.
#include "tracer-node/embree/embree_backend.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <vector>

#include <spdlog/spdlog.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "common/base/timer.h"
#include "common/base/work_unit.h"
#include "common/math/transform.h"
#include "common/render/sealed_emitters.h"
#include "tracer-node/backend/light_choice_log.h"
#include "tracer-node/embree/embree_scene.h"

namespace pathfarm::tracer {
namespace {

// Blocks of 4 rows by 8 pixels handed out in row order from one counter, so the threads end a
// range within one small block of each other. TBB's split of 16x16 tiles left a thread idle
// for about half a tile at the end of every 4-row unit the tracer renders (the farm of one
// tracer with 2 threads lost 4-6 % against pathfarm-render).
constexpr int kBlockRows = 4;
constexpr int kBlockCols = 8;

// Lowers `a` to v unless it is lower already.
void lower_to(std::atomic<int>& a, int v) {
    int current = a;
    while (v < current && !a.compare_exchange_weak(current, v)) {
    }
}

class EmbreeBackend final : public RenderBackend {
public:
    explicit EmbreeBackend(const BackendOptions& options)
        : options_(options),
          arena_(options.threads > 0 ? options.threads : tbb::task_arena::automatic) {}

    std::string name() const override { return "embree"; }

    Status set_scene(const SceneModel& scene) override {
        lights_.reset();
        shading_.reset();
        kernel_.reset();
        const Timer timer;
        Result<std::unique_ptr<EmbreeScene>> kernel =
            Error{ErrorCode::backend_error, "embree: scene not built"};
        arena_.execute([&] { kernel = EmbreeScene::build(scene, options_.threads); });
        if (!kernel) return kernel.error();
        kernel_ = std::move(kernel.value());
        if (options_.texture_lod) mips_.rebuild(scene);
        spdlog::debug("embree backend: scene built in {:.2f} ms", timer.milliseconds());
        adopt(scene);
        return {};
    }

    // Only what `changes` names is redone in Embree: transforms placed, deformed meshes
    // refitted (EmbreeScene). A structural change builds anew.
    Status update_scene(const SceneModel& scene, const SceneChanges& changes) override {
        if (!kernel_ || changes.structure) return set_scene(scene);
        // Only the camera (within its recentring cell) or the settings: the geometry, the
        // light sampler and the closed-surface analysis all hold; culling follows the eye.
        if (&scene == adopted_ && changes.view_only()) return {};
        const Timer timer;
        Result<EmbreeUpdate> u = Error{ErrorCode::backend_error, "embree: scene not updated"};
        arena_.execute([&] { u = kernel_->update(scene, changes); });
        if (!u) return u.error();
        if (options_.texture_lod) mips_.update(scene, changes.textures);
        spdlog::debug(
            "embree backend: update in {:.2f} ms (instances: {} placed, {} re-baked; meshes: {} "
            "re-baked, {} rebuilt; baked BVH {})",
            timer.milliseconds(), u->instances_placed, u->instances_rebaked, u->meshes_rebaked,
            u->meshes_rebuilt, u->baked_rebuilt ? "rebuilt" : "kept");
        adopt(scene);
        return {};
    }

    // Emitters a closed surface separates from this frame's camera are left out of the light
    // sampler; it is rebuilt only when that set changes.
    void update_lights(const RenderJob& job) {
        const Vec3 eye = transform_point(job.frame.camera.camera_to_world, Vec3(0.0f));
        const bool culled_changed = culling_.update(eye, job.integrator.cull_sealed_lights);
        if (!culled_changed && lights_ && lights_->requested() == job.integrator.light_selection)
            return;
        const std::vector<bool>& excluded = culling_.excluded();
        // The light tree is a function of this state alone (every tracer, one that joined late
        // too, must render a frame's rows bit for bit alike: docs/determinism.md); the kept
        // per-mesh topologies make it a refit and a small top level, not a build.
        lights_ = std::make_unique<LightSampler>(*shading_, excluded,
                                                 job.integrator.light_selection, &topology_);
        log_light_choice("embree backend", *lights_, light_in_use_);
        light_in_use_ = lights_->selection();
        spdlog::debug(
            "embree backend: {} emissive instance(s) sealed off from the camera ({} closed "
            "surface(s))",
            std::count(excluded.begin(), excluded.end(), true), culling_.enclosure_count());
    }

    Result<RenderStats> render_rows(const RenderJob& job, float* out) override {
        if (!kernel_)
            return make_error(ErrorCode::invalid_argument,
                              "embree backend: render before set_scene");
        const FrameSpec& f = job.frame;
        if (f.width <= 0 || f.height <= 0 || job.y0 < 0 || job.y1 > f.height || job.y0 > job.y1)
            return make_error(ErrorCode::invalid_argument,
                              "embree backend: rows [{}, {}) outside a {}x{} frame", job.y0, job.y1,
                              f.width, f.height);
        update_lights(job);
        const PathTracer tracer(*shading_, *lights_, *kernel_, job.integrator);
        tbb::enumerable_thread_specific<SampleCounters> counters;
        const Timer timer;
        const int cols = (f.width + kBlockCols - 1) / kBlockCols;
        const int bands = (job.y1 - job.y0 + kBlockRows - 1) / kBlockRows;  // = work units
        std::vector<UnitTally> tally(static_cast<std::size_t>(bands));
        std::atomic<int> next{0}, stopped_at{bands};
        arena_.execute([&] {
            tbb::parallel_for(0, arena_.max_concurrency(), [&](int) {
                SampleCounters& c = counters.local();
                for (int b = next++; b < cols * bands; b = next++) {
                    const int band = b / cols;
                    if (band >= stopped_at) break;
                    if (job.stop && job.stop(job.y0 + band * kBlockRows)) {  // later ones too
                        lower_to(stopped_at, band);
                        break;
                    }
                    render_unit_block(tracer, job, b % cols * kBlockCols, band, out, tally, c);
                }
            });
        });
        RenderStats stats;
        stats.seconds = timer.seconds();
        for (const SampleCounters& c : counters)
            stats.counters.add(c);
        for (int u = 0; u < bands; ++u) {
            const UnitTally& t = tally[std::size_t(u)];
            stats.units.push_back(
                {double(t.ns) * 1e-9, t.rays, u < stopped_at && t.blocks == cols});
        }
        return stats;
    }

    bool times_units() const override { return true; }

private:
    // What the threads add up for one work unit of a render_rows call.
    struct UnitTally {
        std::atomic<int64_t> ns{0};
        std::atomic<uint64_t> rays{0};
        std::atomic<int> blocks{0};
    };
    static_assert(kBlockRows == kRowsPerWorkUnit, "a band of blocks is one work unit");

    // Renders the block at column x of band `band`, timed into that unit's tally.
    static void render_unit_block(const PathTracer& tracer, const RenderJob& job, int x, int band,
                                  float* out, std::vector<UnitTally>& tally, SampleCounters& c) {
        const FrameSpec& f = job.frame;
        const std::size_t stride = std::size_t(f.width) * 3;
        const int y = job.y0 + band * kBlockRows;
        SampleCounters block;
        const Timer timer;
        const std::size_t pixel = std::size_t(y - job.y0) * f.width + x;
        render_block(tracer, f, x, std::min(f.width, x + kBlockCols), y,
                     std::min(job.y1, y + kBlockRows), out + 3 * pixel, stride, block,
                     job.first_hits ? job.first_hits + pixel : nullptr, std::size_t(f.width));
        UnitTally& t = tally[std::size_t(band)];
        t.ns += int64_t(timer.seconds() * 1e9);
        t.rays += block.rays;
        ++t.blocks;
        c.add(block);
    }

    // The integrator's view of `scene`: normal matrices, the sealed-emitter analysis (adopted
    // when only the camera moved), the light sampler rebuilt at the next render.
    void adopt(const SceneModel& scene) {
        adopted_ = &scene;
        lights_.reset();
        shading_ = std::make_unique<ShadingScene>(scene, options_.texture_lod ? &mips_ : nullptr);
        culling_.set_scene(scene);
    }

    BackendOptions options_;
    tbb::task_arena arena_;
    std::unique_ptr<EmbreeScene> kernel_;
    TextureMips mips_;  // kept across updates: rebuilt for changed images only
    std::unique_ptr<ShadingScene> shading_;
    LightCulling culling_;
    LightTopologyCache topology_;  // each emissive mesh's light tree, across states
    std::unique_ptr<LightSampler> lights_;
    // The last light sampler's selection (lights_ is dropped at every scene change): the log
    // says what auto chose when that changes, not at every rebuild.
    std::optional<LightSelection> light_in_use_;
    const SceneModel* adopted_ = nullptr;  // the model shading_ refers to
};

}  // namespace

Result<std::unique_ptr<RenderBackend>> make_embree_backend(const BackendOptions& options) {
    if (options.threads < 0)
        return make_error(ErrorCode::invalid_argument, "--threads {}: must be >= 0",
                          options.threads);
    return std::unique_ptr<RenderBackend>(std::make_unique<EmbreeBackend>(options));
}

}  // namespace pathfarm::tracer
