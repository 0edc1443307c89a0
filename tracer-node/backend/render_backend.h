// RenderBackend: the one small interface every tracer backend implements (STYLE.md §2.3,
// after Cycles' Device). A backend holds a device-side copy of the scene and renders any row
// range [y0, y1) of a frame; the result is the same for every split (docs/determinism.md).
#pragma once

#include <memory>
#include <string>

#include "common/base/result.h"
#include "common/render/frame_render.h"
#include "common/render/path_tracer.h"
#include "common/scene/scene_model.h"

namespace pathfarm::tracer {

struct RenderJob {
    FrameSpec frame;
    IntegratorSettings integrator;
    int y0 = 0;  // rows [y0, y1) of the frame
    int y1 = 0;
};

struct RenderStats {
    double seconds = 0.0;
    SampleCounters counters;
};

class RenderBackend {
public:
    virtual ~RenderBackend() = default;
    virtual std::string name() const = 0;
    // Makes `scene` the scene to render. The model must outlive the backend's use of it.
    virtual Status set_scene(const SceneModel& scene) = 0;
    // Renders rows [job.y0, job.y1) into out: (y1 - y0) rows of width * 3 floats, top row first.
    virtual Result<RenderStats> render_rows(const RenderJob& job, float* out) = 0;
};

enum class BackendKind { embree, opencl };

struct BackendOptions {
    int threads = 0;  // 0: all hardware threads
};

Result<BackendKind> parse_backend_kind(const std::string& name);
Result<std::unique_ptr<RenderBackend>> create_backend(BackendKind kind,
                                                      const BackendOptions& options);

}  // namespace pathfarm::tracer
