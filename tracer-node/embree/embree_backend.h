// The Embree CPU backend: EmbreeScene for rays, the shared integrator for shading, TBB for
// threads (blocks of 4x8 pixels handed out in row order).
#pragma once

#include <memory>

#include "tracer-node/backend/render_backend.h"

namespace pathfarm::tracer {

Result<std::unique_ptr<RenderBackend>> make_embree_backend(const BackendOptions& options);

}  // namespace pathfarm::tracer
