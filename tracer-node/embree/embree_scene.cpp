// Embree 3 scene construction and ray queries.
#include "tracer-node/embree/embree_scene.h"

#include <mutex>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "common/math/transform.h"
#include "common/scene/alpha.h"

namespace pathfarm::tracer {
namespace {

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

// What an alpha-tested geometry's filter needs (glTF MASK / BLEND: common/scene/alpha.h).
struct AlphaGeometry {
    const SceneModel* scene;
    const Mesh* mesh;
};

// Intersection and occlusion filter: rejects hits the material's alpha discards. For instanced
// meshes the ray is in object space; the BLEND hash only needs to be deterministic per ray.
void alpha_filter(const RTCFilterFunctionNArguments* args) {
    const auto* g = static_cast<const AlphaGeometry*>(args->geometryUserPtr);
    const unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] != -1) continue;
        RTCRayN* ray = args->ray;
        RTCHitN* hit = args->hit;
        const Vec3 o(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i));
        const Vec3 d(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i));
        if (!alpha_keeps_hit(*g->scene, *g->mesh, RTCHitN_primID(hit, n, i), RTCHitN_u(hit, n, i),
                             RTCHitN_v(hit, n, i), o, d, RTCRayN_tfar(ray, n, i)))
            args->valid[i] = 0;
    }
}

}  // namespace

struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene top = nullptr;
    std::vector<RTCScene> children;
    std::vector<uint32_t> geometry_instance;  // top-level geomID -> SceneModel instance
    std::vector<std::unique_ptr<AlphaGeometry>> alpha_geometries;  // filter user data
    std::mutex error_mutex;
    std::string first_error;  // first error wins (STYLE.md §5.4)

    ~Impl() {
        for (RTCScene s : children)
            rtcReleaseScene(s);
        if (top) rtcReleaseScene(top);
        if (device) rtcReleaseDevice(device);
    }

    static void on_error(void* user, RTCError code, const char* message) {
        auto* self = static_cast<Impl*>(user);
        std::lock_guard lock(self->error_mutex);
        if (self->first_error.empty())
            self->first_error =
                std::string(embree_error_name(code)) + ": " + (message ? message : "");
    }

    RTCGeometry make_triangles(const SceneModel& scene, const Mesh& mesh, const Mat4* to_world) {
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                              RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                              mesh.positions.size()));
        auto* idx = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(uint32_t), mesh.triangle_count()));
        if (v == nullptr || idx == nullptr) return geom;
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            // Exactly the arithmetic ShadingScene uses, so hits and shading agree.
            const Vec3 p =
                to_world ? transform_point(*to_world, mesh.positions[i]) : mesh.positions[i];
            v[3 * i] = p.x;
            v[3 * i + 1] = p.y;
            v[3 * i + 2] = p.z;
        }
        std::copy(mesh.indices.begin(), mesh.indices.end(), idx);
        if (scene.materials[std::size_t(mesh.material)].alpha_tested()) {
            alpha_geometries.push_back(
                std::make_unique<AlphaGeometry>(AlphaGeometry{&scene, &mesh}));
            rtcSetGeometryUserData(geom, alpha_geometries.back().get());
            rtcSetGeometryIntersectFilterFunction(geom, &alpha_filter);
            rtcSetGeometryOccludedFilterFunction(geom, &alpha_filter);
        }
        rtcCommitGeometry(geom);
        return geom;
    }

    void attach(RTCGeometry geom, uint32_t instance) {
        const uint32_t id = rtcAttachGeometry(top, geom);
        rtcReleaseGeometry(geom);
        if (geometry_instance.size() <= id) geometry_instance.resize(id + 1, 0);
        geometry_instance[id] = instance;
    }

    void build(const SceneModel& scene) {
        top = rtcNewScene(device);
        rtcSetSceneBuildQuality(top, RTC_BUILD_QUALITY_HIGH);
        std::vector<int> uses(scene.meshes.size(), 0);
        for (const Instance& inst : scene.instances)
            ++uses[inst.mesh];
        std::vector<RTCScene> mesh_scene(scene.meshes.size(), nullptr);
        for (uint32_t i = 0; i < scene.instances.size(); ++i) {
            const Instance& inst = scene.instances[i];
            const Mesh& mesh = scene.meshes[inst.mesh];
            if (mesh.triangle_count() == 0) continue;
            if (uses[inst.mesh] == 1) {
                attach(make_triangles(scene, mesh, &inst.transform), i);
                continue;
            }
            if (mesh_scene[inst.mesh] == nullptr) {
                RTCScene child = rtcNewScene(device);
                rtcSetSceneBuildQuality(child, RTC_BUILD_QUALITY_HIGH);
                RTCGeometry geom = make_triangles(scene, mesh, nullptr);
                rtcAttachGeometry(child, geom);
                rtcReleaseGeometry(geom);
                rtcCommitScene(child);
                children.push_back(child);
                mesh_scene[inst.mesh] = child;
            }
            RTCGeometry ig = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(ig, mesh_scene[inst.mesh]);
            rtcSetGeometryTransform(ig, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &inst.transform[0][0]);
            rtcCommitGeometry(ig);
            attach(ig, i);
        }
        rtcCommitScene(top);
    }
};

EmbreeScene::EmbreeScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
EmbreeScene::~EmbreeScene() = default;

Result<std::unique_ptr<EmbreeScene>> EmbreeScene::build(const SceneModel& scene, int threads) {
    auto impl = std::make_unique<Impl>();
    const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : "";
    impl->device = rtcNewDevice(config.c_str());
    if (impl->device == nullptr)
        return make_error(ErrorCode::backend_error, "embree: cannot create device ({})",
                          embree_error_name(rtcGetDeviceError(nullptr)));
    rtcSetDeviceErrorFunction(impl->device, &Impl::on_error, impl.get());
    impl->build(scene);
    if (!impl->first_error.empty())
        return make_error(ErrorCode::backend_error, "embree: scene build failed: {}",
                          impl->first_error);
    return std::unique_ptr<EmbreeScene>(new EmbreeScene(std::move(impl)));
}

bool EmbreeScene::intersect(const Ray& ray, Hit& hit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x;
    rh.ray.org_y = ray.o.y;
    rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x;
    rh.ray.dir_y = ray.d.y;
    rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = ray.tmax;
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xffffffffU;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->top, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    const uint32_t top_id =
        rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? rh.hit.instID[0] : rh.hit.geomID;
    hit.t = rh.ray.tfar;
    hit.instance = impl_->geometry_instance[top_id];
    hit.prim = rh.hit.primID;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    return true;
}

bool EmbreeScene::occluded(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.tnear = 0.0f;
    r.tfar = ray.tmax;
    r.time = 0.0f;
    r.mask = 0xffffffffU;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(impl_->top, &context, &r);
    return r.tfar < 0.0f;
}

}  // namespace pathfarm::tracer
