// Embree 3 two-level scene: construction, incremental updates and ray queries.
#include "tracer-node/embree/embree_scene.h"

#include <algorithm>
#include <mutex>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "tracer-node/embree/embree_geometry.h"

namespace pathfarm::tracer {
namespace {

// Up to this many baked triangles share the top level with the instances of shared meshes
// (a top-level commit rebuilds them: about 2 ms at this size).
constexpr std::size_t kFlatTopTriangles = 4000;

// A mesh placed by several instances: its own scene in object space, instanced.
struct SharedMesh {
    RTCScene scene = nullptr;
    TriangleGeometry tri;
    std::vector<uint32_t> users;  // the instances placing it
};

}  // namespace

// Meshes placed once are baked in model space into one BVH (rays traverse it as fast as a flat
// scene): the top level itself, or, with shared meshes and over kFlatTopTriangles, a scene of
// its own that every query traverses first and the top level then with what is left of the
// ray (under an identity instance in the top level, each ray paid the instance: 4.3 % more
// instructions on builtin:default). Meshes placed several times, and dynamic instances' meshes,
// keep a scene of their own, instanced. A camera move within its recentring cell changes
// nothing here; a moved instance re-bakes its triangles or moves its instance.
struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene top = nullptr;
    RTCScene baked = nullptr;  // the top level, or the baked triangles' scene traced before it
    bool packets = false;      // the device traces 8-ray packets natively
    std::vector<TriangleGeometry> bakes;  // by SceneModel instance (geom null: not baked)
    std::vector<SharedMesh> shared;       // by SceneModel mesh (scene null: not shared)
    std::vector<RTCGeometry> placements;  // by SceneModel instance: its instance of a shared mesh
    std::mutex error_mutex;
    std::string first_error;  // first error wins (STYLE.md §5.4)

    ~Impl() {
        for (SharedMesh& m : shared)
            if (m.scene) rtcReleaseScene(m.scene);
        if (baked) rtcReleaseScene(baked);
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

    // A committed triangle geometry of mesh `index`, attached to `scene` as `id`.
    void make_triangles(TriangleGeometry& g, const SceneModel& scene, uint32_t index,
                        const Mat4* to_model, RTCScene into, uint32_t id) {
        const Mesh& mesh = scene.meshes[index];
        g.geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        g.vertex_count = 0;
        write_positions(g, mesh, to_model);
        auto* idx = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(g.geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(uint32_t), mesh.triangle_count()));
        if (idx) std::copy(mesh.indices.begin(), mesh.indices.end(), idx);
        *g.alpha = AlphaGeometry{&scene, index};
        rtcSetGeometryUserData(g.geom, g.alpha.get());
        g.filtered = false;
        follow_material(g, scene);
        rtcCommitGeometry(g.geom);
        rtcAttachGeometryByID(into, g.geom, id);
        rtcReleaseGeometry(g.geom);  // the scene keeps it
    }

    // (Re)builds shared mesh `index`'s scene at high quality; its instances follow. A deformed
    // mesh is built again, not refitted: Embree's refit representation (RTC_BUILD_QUALITY_REFIT
    // in a low-quality scene) intersects with other arithmetic than a fresh build, so a tracer
    // that refitted would render other bits than one that joined later (IncrementalUpdate.*).
    void build_shared(const SceneModel& scene, uint32_t index) {
        SharedMesh& m = shared[index];
        if (m.scene) rtcReleaseScene(m.scene);
        m.scene = rtcNewScene(device);
        rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
        make_triangles(m.tri, scene, index, nullptr, m.scene, 0);
        rtcCommitScene(m.scene);
        for (uint32_t i : m.users)
            if (placements[i]) {
                rtcSetGeometryInstancedScene(placements[i], m.scene);
                rtcCommitGeometry(placements[i]);
            }
    }

    void place(uint32_t i, const Instance& inst) {
        rtcSetGeometryTransform(placements[i], 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR,
                                &inst.transform[0][0]);
        rtcCommitGeometry(placements[i]);
    }

    RTCGeometry attach_instance(RTCScene child, uint32_t id, const Mat4& transform) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, child);
        rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &transform[0][0]);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(top, g, id);
        rtcReleaseGeometry(g);  // the top level keeps it
        return g;
    }

    void build(const SceneModel& scene) {
        const uint32_t count = uint32_t(scene.instances.size());
        bakes.resize(count);
        placements.assign(count, nullptr);
        shared.resize(scene.meshes.size());
        for (uint32_t i = 0; i < count; ++i)
            if (scene.meshes[scene.instances[i].mesh].triangle_count() > 0)
                shared[scene.instances[i].mesh].users.push_back(i);
        // Baked triangles sit in the top level itself unless there are shared meshes to move and
        // so many baked triangles that rebuilding them with every move costs more than tracing
        // two scenes costs rays; rebuilding takes about 0.3-0.8 us per triangle on two threads.
        // In the demo, where builtin:default's ball rolls every frame, the flat top level cost
        // each tracer 8.5 ms a frame (11 % of its time); with the baked scene apart, 0.06 ms.
        // A dynamic instance of a mesh placed once is instanced like a shared mesh's: moving it
        // is then a top-level commit, not a build of every baked triangle.
        std::size_t baked_triangles = 0;
        bool any_instanced = false;
        for (std::size_t m = 0; m < shared.size(); ++m) {
            if (baked_mesh(scene, m))
                baked_triangles += scene.meshes[m].triangle_count();
            else
                any_instanced |= !shared[m].users.empty();
        }
        top = rtcNewScene(device);
        baked = any_instanced && baked_triangles > kFlatTopTriangles ? rtcNewScene(device) : top;
        if (baked == top) rtcRetainScene(top);  // released as `baked` and as `top`
        rtcSetSceneBuildQuality(baked, RTC_BUILD_QUALITY_HIGH);
        for (uint32_t i = 0; i < count; ++i) {
            const uint32_t mesh = scene.instances[i].mesh;
            if (baked_mesh(scene, mesh)) {
                make_triangles(bakes[i], scene, mesh, &scene.instances[i].transform, baked, i);
            } else if (!shared[mesh].users.empty()) {
                if (!shared[mesh].scene) build_shared(scene, mesh);
                placements[i] =
                    attach_instance(shared[mesh].scene, i, scene.instances[i].transform);
            }
        }
        if (baked != top) rtcCommitScene(baked);
        rtcCommitScene(top);
    }

    // An Embree hit as the integrator's: baked triangles carry their instance's index as
    // geometry ID, placements as instance ID.
    static Hit to_hit(float t, unsigned geom, unsigned placed, unsigned prim, float u, float v) {
        return {t, placed == RTC_INVALID_GEOMETRY_ID ? geom : placed, prim, u, v};
    }

    // A baked scene apart from the top level: queries traverse it first.
    bool baked_apart() const { return baked != top; }

    bool is_baked(uint32_t instance) const { return bakes[instance].geom != nullptr; }
    // Mesh m is placed once, by an instance that is not dynamic: its triangles are baked.
    bool baked_mesh(const SceneModel& scene, std::size_t m) const {
        return shared[m].users.size() == 1 && !scene.instances[shared[m].users[0]].dynamic;
    }

    // Writes baked instance i's triangles where its transform and mesh now put them.
    void rebake_instance(const SceneModel& scene, uint32_t i) {
        TriangleGeometry& g = bakes[i];
        write_positions(g, scene.meshes[scene.instances[i].mesh], &scene.instances[i].transform);
        rtcCommitGeometry(g.geom);
    }

    // New vertices for mesh `index`: re-baked if it is placed once (true), else its scene is
    // built again (false).
    bool deform(const SceneModel& scene, uint32_t index) {
        const SharedMesh& m = shared[index];
        if (m.users.size() == 1 && is_baked(m.users[0])) {
            rebake_instance(scene, m.users[0]);
            return true;
        }
        build_shared(scene, index);
        return false;
    }

    EmbreeUpdate update(const SceneModel& scene, const SceneChanges& changes);
};

EmbreeUpdate EmbreeScene::Impl::update(const SceneModel& scene, const SceneChanges& changes) {
    EmbreeUpdate u;
    bool rebake = false, top_dirty = false;
    for (TriangleGeometry& g : bakes)
        g.alpha->scene = &scene;
    for (SharedMesh& m : shared)
        m.tri.alpha->scene = &scene;
    for (uint32_t index : changes.mesh_vertices) {
        if (index >= shared.size() || shared[index].users.empty()) continue;
        const bool rebaked = deform(scene, index);
        (rebaked ? u.meshes_rebaked : u.meshes_rebuilt) += 1;
        rebake |= rebaked;
        top_dirty |= !rebaked;
    }
    for (uint32_t i : changes.instances) {
        if (i >= bakes.size()) continue;
        if (is_baked(i)) {
            rebake_instance(scene, i);
            ++u.instances_rebaked;
            rebake = true;
        } else if (placements[i]) {
            place(i, scene.instances[i]);
            ++u.instances_placed;
            top_dirty = true;
        }
    }
    if (!changes.materials.empty()) {
        for (TriangleGeometry& g : bakes)
            if (g.geom && follow_material(g, scene)) {
                rtcCommitGeometry(g.geom);
                rebake = true;
            }
        for (SharedMesh& m : shared)
            if (m.scene && follow_material(m.tri, scene)) {
                rtcCommitGeometry(m.tri.geom);
                rtcCommitScene(m.scene);
                top_dirty = true;
            }
    }
    if (rebake && baked_apart()) rtcCommitScene(baked);  // a full build of the baked BVH
    u.baked_rebuilt = rebake;
    if (top_dirty || (rebake && !baked_apart())) rtcCommitScene(top);
    return u;
}

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
    impl->packets =
        rtcGetDeviceProperty(impl->device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0;
    impl->build(scene);
    if (!impl->first_error.empty())
        return make_error(ErrorCode::backend_error, "embree: scene build failed: {}",
                          impl->first_error);
    return std::unique_ptr<EmbreeScene>(new EmbreeScene(std::move(impl)));
}

Result<EmbreeUpdate> EmbreeScene::update(const SceneModel& scene, const SceneChanges& changes) {
    if (changes.structure || scene.instances.size() != impl_->bakes.size() ||
        scene.meshes.size() != impl_->shared.size())
        return make_error(ErrorCode::invalid_argument,
                          "embree: a structural change needs a new scene, not an update");
    const EmbreeUpdate u = impl_->update(scene, changes);
    if (!impl_->first_error.empty())
        return make_error(ErrorCode::backend_error, "embree: scene update failed: {}",
                          impl_->first_error);
    return u;
}

bool EmbreeScene::baked_apart() const { return impl_->baked_apart(); }

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
    bool found = false;
    if (impl_->baked_apart()) {  // then the top level, for hits nearer than this one
        rtcIntersect1(impl_->baked, &context, &rh);
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
            found = true;
            hit = Impl::to_hit(rh.ray.tfar, rh.hit.geomID, RTC_INVALID_GEOMETRY_ID, rh.hit.primID,
                               rh.hit.u, rh.hit.v);
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;  // as Embree requires of every query
        }
    }
    rtcIntersect1(impl_->top, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return found;
    hit = Impl::to_hit(rh.ray.tfar, rh.hit.geomID, rh.hit.instID[0], rh.hit.primID, rh.hit.u,
                       rh.hit.v);
    return true;
}

void EmbreeScene::intersect_coherent(const Ray* rays, int count, Hit* hits, bool* found) const {
    if (!impl_->packets || count < 2) {
        Intersector::intersect_coherent(rays, count, hits, found);
        return;
    }
    static_assert(kCoherentWidth == 8, "one RTCRayHit8 per call");
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    RTCRayHit8 rh;
    int valid[8];
    for (int i = 0; i < 8; ++i) {
        const Ray& r = rays[std::min(i, count - 1)];  // inactive lanes copy a real ray
        valid[i] = i < count ? -1 : 0;
        rh.ray.org_x[i] = r.o.x;
        rh.ray.org_y[i] = r.o.y;
        rh.ray.org_z[i] = r.o.z;
        rh.ray.dir_x[i] = r.d.x;
        rh.ray.dir_y[i] = r.d.y;
        rh.ray.dir_z[i] = r.d.z;
        rh.ray.tnear[i] = 0.0f;
        rh.ray.tfar[i] = r.tmax;
        rh.ray.time[i] = 0.0f;
        rh.ray.mask[i] = 0xffffffffU;
        rh.ray.id[i] = unsigned(i);
        rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    bool in_baked[8] = {};
    if (impl_->baked_apart()) {  // as intersect() does, lane by lane
        rtcIntersect8(valid, impl_->baked, &context, &rh);
        for (int i = 0; i < count; ++i) {
            in_baked[i] = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
            if (in_baked[i])
                hits[i] = Impl::to_hit(rh.ray.tfar[i], rh.hit.geomID[i], RTC_INVALID_GEOMETRY_ID,
                                       rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i]);
            rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        }
    }
    rtcIntersect8(valid, impl_->top, &context, &rh);
    for (int i = 0; i < count; ++i) {
        found[i] = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        if (found[i])
            hits[i] = Impl::to_hit(rh.ray.tfar[i], rh.hit.geomID[i], rh.hit.instID[0][i],
                                   rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i]);
        else
            found[i] = in_baked[i];
    }
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
    if (impl_->baked_apart()) {  // most occluders are baked: the top level only if it is not
        rtcOccluded1(impl_->baked, &context, &r);
        if (r.tfar < 0.0f) return true;
    }
    rtcOccluded1(impl_->top, &context, &r);
    return r.tfar < 0.0f;
}

}  // namespace pathfarm::tracer
