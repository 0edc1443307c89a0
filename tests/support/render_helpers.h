// Rendering helpers for tests: scenes with analytic answers and one-call renders through a
// backend.
#pragma once

#include <string>
#include <vector>

#include "common/film/film.h"
#include "common/render/path_tracer.h"
#include "common/scene/scene_model.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::test {

// The backend test renders use unless a test names one: Embree, or the one named by the
// PATHFARM_TEST_BACKEND environment variable (ctest runs the stress suite again with "opencl").
tracer::BackendKind default_backend();

// The backends a render test is parameterised over: Embree, and OpenCL where the test target
// defines PATHFARM_HAS_OPENCL (inline so that each target's own definition counts).
inline std::vector<tracer::BackendKind> built_backends() {
#ifdef PATHFARM_HAS_OPENCL
    return {tracer::BackendKind::embree, tracer::BackendKind::opencl};
#else
    return {tracer::BackendKind::embree};
#endif
}

// "embree" or "opencl", for test names.
inline const char* backend_label(tracer::BackendKind kind) {
    return kind == tracer::BackendKind::embree ? "embree" : "opencl";
}

// The name generator of suites parameterised by backend alone.
struct BackendTestName {
    template <typename ParamInfo>
    std::string operator()(const ParamInfo& param_info) const {
        return backend_label(param_info.param);
    }
};

struct RenderRequest {
    int width = 32;
    int height = 32;
    int spp = 16;
    uint32_t seed = 0;
    uint32_t frame = 0;
    int threads = 2;
    bool texture_lod = true;  // BackendOptions::texture_lod
    IntegratorSettings integrator;
    std::vector<int> row_splits;  // render [0,s0), [s0,s1), ... [sN,height) separately
    tracer::BackendKind backend = default_backend();
};

// Renders with the requested backend (Embree by default); fails the test (and returns an
// empty image) on error.
FloatImage render(const SceneModel& scene, const RenderRequest& request);
// `count` renders with seeds request.seed, request.seed + 1, ... through one backend (batch
// means for the statistical tests without a backend and scene build per batch).
std::vector<FloatImage> render_seeds(const SceneModel& scene, const RenderRequest& request,
                                     int count);

// Every surface emits `emission` and reflects with Lambert albedo `albedo`: a sphere inside
// a spherical enclosure. Every pixel converges to emission / (1 - albedo).
SceneModel make_furnace(float emission, float albedo);
// A Lambert sphere of albedo rho inside a black enclosure emitting `emission` inwards:
// sphere pixels converge to rho * emission, the rest to emission.
SceneModel make_lit_sphere(float emission, float rho);

// Per-pixel Welch t-tests between two sets of batch images (independent seeds), Šidák-
// corrected over all pixels and channels, plus one test on the image mean.
struct AgreementResult {
    double min_pixel_p = 1.0;
    double pixel_threshold = 0.0;  // Šidák per-test level
    double mean_p = 1.0;
    std::size_t worst_value = 0;          // index into rgb of the least agreeing pixel channel
    double worst_a = 0.0, worst_b = 0.0;  // its means in a and b
    bool agree(double alpha) const { return min_pixel_p >= pixel_threshold && mean_p >= alpha; }
};
// block > 1 averages block x block pixel squares first: for sparse, heavy-tailed estimators
// (BSDF sampling of a small light) per-pixel batch means are far from normal. Where one side's
// batches are all equal (black), the other is tested against that value, unless that side is b
// and b_sparse says b may miss a small contribution in every batch (BSDF-only sampling).
AgreementResult compare_batches(const std::vector<FloatImage>& a, const std::vector<FloatImage>& b,
                                double alpha, int block = 1, bool b_sparse = false);

// Two-sided p-value of Student's t with `dof` degrees of freedom.
double student_t_p_value(double t, double dof);

}  // namespace pathfarm::test
