// RenderBackend: the one small interface every tracer backend implements (STYLE.md §2.3,
// after Cycles' Device). A backend holds a device-side copy of the scene and renders any row
// range [y0, y1) of a frame; the result is the same for every split (docs/determinism.md).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/render/frame_render.h"
#include "common/render/path_tracer.h"
#include "common/scene/bvh_node.h"
#include "common/scene/scene_model.h"

namespace pathfarm::tracer {

struct RenderJob {
    FrameSpec frame;
    IntegratorSettings integrator;
    int y0 = 0;  // rows [y0, y1) of the frame
    int y1 = 0;
    // Backends that time units (RenderBackend::times_units) ask this before each piece of work
    // with the first row of its work unit: true leaves that unit and every later one unrendered
    // (the rows went to another tracer, or the frame closed). Empty: render everything.
    std::function<bool(int unit_y0)> stop;
    // Where the first hits of rows [y0, y1) go ((y1 - y0) * width of them, row-major), or null
    // when nobody wants them.
    FirstHit* first_hits = nullptr;
};

// One work unit (kRowsPerWorkUnit rows from RenderJob::y0) of a range rendered in one call.
struct UnitStats {
    double seconds = 0.0;  // thread time spent on it (its cost; summed over threads)
    uint64_t rays = 0;
    bool rendered = false;  // every pixel of it (false: stopped before or during it)
};

struct RenderStats {
    double seconds = 0.0;
    SampleCounters counters;
    std::vector<UnitStats> units;  // filled by backends that time units, else empty
};

// A mesh's BVH as the coordinator built it (common/scene/bvh.h layout), for backends that
// traverse the coordinator's BVH themselves (DESIGN.md: the OpenCL tracer).
struct MeshBvhView {
    const std::vector<BvhNode>* nodes = nullptr;
    const std::vector<uint32_t>* prim_indices = nullptr;
};

// What changed in the scene since the backend last saw it (DESIGN.md, "The frame" step 5), as
// indices into the SceneModel that comes with it, so a backend can update only that. The first
// scene, and any change that adds or removes objects (indices may have moved), has `structure`.
struct SceneChanges {
    bool structure = false;
    std::vector<uint32_t> instances;      // transforms; a camera move into another recentring
                                          // cell shifts them all (scene_model.h)
    std::vector<uint32_t> mesh_vertices;  // deformed meshes (positions, normals, tangents)
    std::vector<uint32_t> materials;      // any parameter, emission included
    std::vector<uint32_t> textures;       // a texture or its image
    bool lights = false;                  // what emits light changed: an emissive material, an
                                          // emitter that moved or deformed, the sun/sky
    bool camera = false;
    bool settings = false;
    bool environment = false;

    static SceneChanges everything();
    bool empty() const;
    // Only the camera (within its recentring cell) or the render settings changed: the
    // geometry, materials and lights a backend holds are what they were. (Inline: the backend
    // libraries use it and sit below this one's library.)
    bool view_only() const {
        return !structure && instances.empty() && mesh_vertices.empty() && materials.empty() &&
               textures.empty() && !lights && !environment;
    }
};

// What differs between two scenes with the same objects (a tool's or a test's view of a
// commit): instances whose transform differs, meshes whose positions differ, and the camera.
SceneChanges diff_scenes(const SceneModel& before, const SceneModel& after);

// A sequence of world-space scenes as a tracer's backend sees them, for tools, tests and
// benchmarks: each step diffs against the previous scene and recentres, as the tracer does.
class SceneStepper {
public:
    // The change set that takes the backend from the last scene() to the new one.
    SceneChanges step(SceneModel world);
    const SceneModel& scene() const { return current_; }  // camera-relative: hand this over
    const SceneModel& world() const { return previous_; }

private:
    SceneModel previous_, current_;
    bool started_ = false;
};

// Camera-relative rendering for a backend (scene_model.h): recentres `scene` (in world space)
// on its first camera; when the origin left `previous_origin`'s cell, every instance moved.
void recentre_for_backend(SceneModel& scene, const glm::dvec3& previous_origin,
                          SceneChanges& changes);

class RenderBackend {
public:
    virtual ~RenderBackend() = default;
    virtual std::string name() const = 0;
    // Whether this backend traverses the coordinator's BVH (its tracer asks for BVH nodes).
    virtual bool wants_bvh_nodes() const { return false; }
    // BVHs for the next set_scene, indexed like SceneModel::meshes (the views must outlive that
    // call). A mesh without one (or with an invalid one) gets a BVH built by the backend.
    virtual void provide_mesh_bvhs(std::vector<MeshBvhView> /*bvhs*/) {}
    // Makes `scene` the scene to render. The model must outlive the backend's use of it.
    virtual Status set_scene(const SceneModel& scene) = 0;
    // Makes `scene` the scene to render after `changes` (what changed since the last call).
    // The default rebuilds everything; a backend may update only what `changes` names.
    virtual Status update_scene(const SceneModel& scene, const SceneChanges& changes) {
        (void)changes;
        return set_scene(scene);
    }
    // Renders rows [job.y0, job.y1) into out: (y1 - y0) rows of width * 3 floats, top row first.
    virtual Result<RenderStats> render_rows(const RenderJob& job, float* out) = 0;
    // Whether render_rows times each work unit of a longer range (RenderStats::units) and
    // honours RenderJob::stop, so a tracer can render a whole tile in one parallel call instead
    // of one call per unit (whose threads meet at every unit's end).
    virtual bool times_units() const { return false; }
};

enum class BackendKind { embree, opencl };

struct BackendOptions {
    int threads = 0;      // 0: all hardware threads (OpenCL: all compute units of the device)
    int cl_platform = 0;  // OpenCL platform and device, as listed by --list-devices
    int cl_device = 0;
    // Coarser texture levels past a path's first hit (common/scene/texture_mips.h); false
    // reads level 0 everywhere, for measuring what the levels save and what they cost.
    bool texture_lod = true;
};

Result<BackendKind> parse_backend_kind(const std::string& name);
Result<std::unique_ptr<RenderBackend>> create_backend(BackendKind kind,
                                                      const BackendOptions& options);

}  // namespace pathfarm::tracer
