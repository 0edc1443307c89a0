// The Embree CPU backend: EmbreeScene for rays, the shared integrator for shading, TBB for
// threads (tiles of 16x16 pixels).
#pragma once

#include <memory>

#include "tracer-node/backend/render_backend.h"

namespace pathfarm::tracer {

Result<std::unique_ptr<RenderBackend>> make_embree_backend(const BackendOptions& options);

}  // namespace pathfarm::tracer
