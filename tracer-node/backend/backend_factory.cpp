// The single place that names concrete backends (as Cycles' Device::create).
#include "tracer-node/backend/render_backend.h"

#ifdef PATHFARM_HAS_EMBREE
#include "tracer-node/embree/embree_backend.h"
#endif
#ifdef PATHFARM_HAS_OPENCL
#include "tracer-node/opencl/opencl_backend.h"
#endif

namespace pathfarm::tracer {

Result<BackendKind> parse_backend_kind(const std::string& name) {
    if (name == "embree") return BackendKind::embree;
    if (name == "opencl") return BackendKind::opencl;
    return make_error(ErrorCode::invalid_argument,
                      "--backend {}: unknown backend (embree or opencl)", name);
}

// `options` is unused in a build without either backend (the sanitizer build).
Result<std::unique_ptr<RenderBackend>> create_backend(
    BackendKind kind, [[maybe_unused]] const BackendOptions& options) {
    switch (kind) {
        case BackendKind::embree:
#ifdef PATHFARM_HAS_EMBREE
            return make_embree_backend(options);
#else
            return make_error(ErrorCode::unsupported,
                              "embree backend: not built (PATHFARM_WITH_EMBREE=OFF)");
#endif
        case BackendKind::opencl:
        default:
#ifdef PATHFARM_HAS_OPENCL
        {
            auto backend = make_opencl_backend(options);
            if (!backend) return backend.error();
            return std::unique_ptr<RenderBackend>(std::move(backend.value()));
        }
#else
            return make_error(ErrorCode::unsupported,
                              "opencl backend: not built (PATHFARM_WITH_OPENCL=OFF)");
#endif
    }
}

}  // namespace pathfarm::tracer
