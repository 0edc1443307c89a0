// Embree triangle geometries: vertex buffers from meshes, and the alpha filter.
#include "tracer-node/embree/embree_geometry.h"

#include "common/math/transform.h"
#include "common/scene/alpha.h"

namespace pathfarm::tracer {
namespace {

// Intersection and occlusion filter: rejects hits the material's alpha discards. The ray is in
// the mesh's object space; the BLEND hash only needs to be deterministic per ray.
void alpha_filter(const RTCFilterFunctionNArguments* args) {
    const auto* g = static_cast<const AlphaGeometry*>(args->geometryUserPtr);
    const Mesh& mesh = g->scene->meshes[g->mesh];
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] != -1) continue;
        RTCRayN* ray = args->ray;
        RTCHitN* hit = args->hit;
        const Vec3 o(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i));
        const Vec3 d(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i));
        if (!alpha_keeps_hit(*g->scene, mesh, RTCHitN_primID(hit, n, i), RTCHitN_u(hit, n, i),
                             RTCHitN_v(hit, n, i), o, d, RTCRayN_tfar(ray, n, i)))
            args->valid[i] = 0;
    }
}

}  // namespace

const char* embree_error_name(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE:
            return "RTC_ERROR_NONE";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "RTC_ERROR_INVALID_ARGUMENT";
        case RTC_ERROR_INVALID_OPERATION:
            return "RTC_ERROR_INVALID_OPERATION";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "RTC_ERROR_OUT_OF_MEMORY";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "RTC_ERROR_UNSUPPORTED_CPU";
        case RTC_ERROR_CANCELLED:
            return "RTC_ERROR_CANCELLED";
        default:
            return "RTC_ERROR_UNKNOWN";
    }
}

void write_positions(TriangleGeometry& g, const Mesh& mesh, const Mat4* to_model) {
    if (g.vertex_count != mesh.positions.size()) {
        rtcSetNewGeometryBuffer(g.geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), mesh.positions.size());
        g.vertex_count = mesh.positions.size();
    }
    auto* v = static_cast<float*>(rtcGetGeometryBufferData(g.geom, RTC_BUFFER_TYPE_VERTEX, 0));
    if (v == nullptr) return;  // the device reported the error
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const Vec3 p = to_model ? transform_point(*to_model, mesh.positions[i]) : mesh.positions[i];
        v[3 * i] = p.x;
        v[3 * i + 1] = p.y;
        v[3 * i + 2] = p.z;
    }
    rtcUpdateGeometryBuffer(g.geom, RTC_BUFFER_TYPE_VERTEX, 0);
}

bool follow_material(TriangleGeometry& g, const SceneModel& scene) {
    const Mesh& mesh = scene.meshes[g.alpha->mesh];
    const bool wanted = scene.materials[std::size_t(mesh.material)].alpha_tested();
    if (wanted == g.filtered) return false;
    g.filtered = wanted;
    rtcSetGeometryIntersectFilterFunction(g.geom, wanted ? &alpha_filter : nullptr);
    rtcSetGeometryOccludedFilterFunction(g.geom, wanted ? &alpha_filter : nullptr);
    return true;
}

}  // namespace pathfarm::tracer
