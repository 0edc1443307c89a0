// The OpenCL backend: the scene in device buffers (device_scene.h), updated by uploading only
// what changed since the last set_scene, and the path tracer as OpenCL C kernels (kernels/),
// built once per process and feature variant. Runs on any OpenCL 1.2 device; CI uses PoCL.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "tracer-node/backend/render_backend.h"

namespace pathfarm::tracer {

// Bytes written to the device by the last set_scene, per buffer ("instances", "positions", ...).
struct UploadStats {
    std::map<std::string, std::size_t> bytes;
    std::size_t total() const;
};

class OpenClBackend : public RenderBackend {
public:
    ~OpenClBackend() override;
    std::string name() const override { return "opencl"; }
    bool wants_bvh_nodes() const override { return true; }
    void provide_mesh_bvhs(std::vector<MeshBvhView> bvhs) override;
    Status set_scene(const SceneModel& scene) override;
    // Re-packs and diff-uploads the scene, except when only the view changed (nothing to do).
    Status update_scene(const SceneModel& scene, const SceneChanges& changes) override;
    Result<RenderStats> render_rows(const RenderJob& job, float* out) override;

    const UploadStats& last_upload() const;
    // Meshes of the current scene whose BVH this tracer built (no valid one was provided).
    std::size_t meshes_with_own_bvh() const;
    std::string device_name() const;

    struct Impl;

private:
    explicit OpenClBackend(std::unique_ptr<Impl> impl);
    Status update_lights(const RenderJob& job);
    // Packs `scene` with the mips as they are and uploads what differs from the device's copy.
    Status upload_scene(const SceneModel& scene);
    friend Result<std::unique_ptr<OpenClBackend>> make_opencl_backend(const BackendOptions&);
    std::unique_ptr<Impl> impl_;
};

// Opens platform options.cl_platform, device options.cl_device. Fails with one line naming
// the problem when there is no OpenCL platform or device, or the indices are out of range.
Result<std::unique_ptr<OpenClBackend>> make_opencl_backend(const BackendOptions& options);

// One line per platform and device ("0.0 Portable Computing Language: cpu-...").
Result<std::vector<std::string>> list_opencl_devices();

}  // namespace pathfarm::tracer
