// OpenClBackend: scene buffers updated by diff, light culling, and the row-range launch.
#include "tracer-node/opencl/opencl_backend.h"

#include <spdlog/spdlog.h>

#include "common/base/timer.h"
#include "common/math/transform.h"
#include "common/render/sealed_emitters.h"
#include "tracer-node/backend/light_choice_log.h"
#include "tracer-node/opencl/cl_device.h"
#include "tracer-node/opencl/device_array.h"
#include "tracer-node/opencl/device_scene.h"

namespace pathfarm::tracer {

std::size_t UploadStats::total() const {
    std::size_t t = 0;
    for (const auto& [name, n] : bytes)
        t += n;
    return t;
}

struct OpenClBackend::Impl {
    std::shared_ptr<SharedDevice> shared;
    cl::CommandQueue queue;
    std::vector<MeshBvhView> provided_bvhs;
    LocalBvhCache bvh_cache;
    bool has_scene = false;
    uint32_t features = kAllFeatures;
    std::size_t own_bvhs = 0;
    UploadStats upload;
    // For re-packing the lights when the camera's side of a closed surface changes.
    const SceneModel* scene = nullptr;
    LightCulling culling;
    PackedScene light_state;  // instances, lights and globals as last uploaded
    LightSelection light_selection = LightSelection::power;  // as last packed
    std::optional<LightSelection> light_in_use;              // what that resolved to (for the log)
    LightTopologyCache light_topology;                       // each emissive mesh's light tree
    bool texture_lod = true;                                 // BackendOptions::texture_lod
    TextureMips mips;  // kept across updates: rebuilt for changed images only
    // Scene buffers (device_types.h PF_SCENE_ARRAYS), then the globals.
#define PF_DEVICE_ARRAY(name, type) DeviceArray name;
    PF_SCENE_ARRAYS(PF_DEVICE_ARRAY)
#undef PF_DEVICE_ARRAY
    DeviceArray globals;
    std::map<uint32_t, cl::Kernel> kernels;  // by variant
    cl::Buffer out, counters, first_hits, extra_samples;
    std::size_t out_capacity = 0;
    std::vector<uint32_t> counter_host;

    Result<cl::Kernel> kernel(uint32_t variant) {
        if (auto it = kernels.find(variant); it != kernels.end()) return it->second;
        auto program = shared->program(variant);
        if (!program) return program.error();
        cl_int err = CL_SUCCESS;
        cl::Kernel k(*program, "pf_render_rows", &err);
        if (err != CL_SUCCESS) return cl_failure("creating kernel pf_render_rows", err);
        kernels.emplace(variant, k);
        return k;
    }

    template <typename T>
    Status upload_array(const char* name, DeviceArray& array, const std::vector<T>& data) {
        auto n =
            array.assign(shared->context, queue, data.data(), data.size() * sizeof(T), sizeof(T));
        if (!n) return n.error();
        upload.bytes[name] = *n;
        return {};
    }

    Status reserve_output(std::size_t pixels);
    Status upload_extra_samples(const RenderJob& job);
    Status set_arguments(cl::Kernel& k, const PfFrameParams& fp);
    Result<SampleCounters> launch(cl::Kernel& k, int width, std::size_t rows, float* pixels_out,
                                  FirstHit* hits_out);
};

OpenClBackend::OpenClBackend(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OpenClBackend::~OpenClBackend() = default;

void OpenClBackend::provide_mesh_bvhs(std::vector<MeshBvhView> bvhs) {
    impl_->provided_bvhs = std::move(bvhs);
}

const UploadStats& OpenClBackend::last_upload() const { return impl_->upload; }
std::size_t OpenClBackend::meshes_with_own_bvh() const { return impl_->own_bvhs; }
std::string OpenClBackend::device_name() const { return impl_->shared->name; }

Status OpenClBackend::update_scene(const SceneModel& scene, const SceneChanges& changes) {
    Impl& d = *impl_;
    if (d.has_scene && d.scene == &scene && changes.view_only()) {
        // The packed scene would be the same bytes (the camera goes with each frame's
        // parameters; culling follows the eye at render): skip packing and diffing.
        d.provided_bvhs.clear();
        d.upload = {};
        return {};
    }
    if (!d.has_scene || changes.structure) return set_scene(scene);
    if (d.texture_lod) d.mips.update(scene, changes.textures);
    return upload_scene(scene);
}

Status OpenClBackend::set_scene(const SceneModel& scene) {
    if (impl_->texture_lod) impl_->mips.rebuild(scene);
    return upload_scene(scene);
}

Status OpenClBackend::upload_scene(const SceneModel& scene) {
    Impl& d = *impl_;
    const Timer timer;
    const PackedScene p =
        pack_scene(scene, d.provided_bvhs, d.bvh_cache, d.texture_lod ? &d.mips : nullptr);
    const double pack_ms = timer.milliseconds();
    d.provided_bvhs.clear();  // views are valid for this call only
    d.upload = {};
    const std::vector<PfSceneGlobals> globals{p.globals};
#define PF_UPLOAD(name, type) d.upload_array(#name, d.name, p.name),
    for (Status s : {PF_SCENE_ARRAYS(PF_UPLOAD) d.upload_array("globals", d.globals, globals)})
        if (!s) return s;
#undef PF_UPLOAD
    if (const cl_int err = d.queue.finish(); err != CL_SUCCESS)
        return cl_failure("uploading the scene", err);
    d.features = p.features;
    d.own_bvhs = p.meshes_with_own_bvh;
    d.has_scene = true;
    d.scene = &scene;
    d.culling.set_scene(scene);
    d.light_state.instances = p.instances;
    d.light_state.globals = p.globals;
    d.light_selection = LightSelection::power;  // pack_scene's
    std::string parts;
    for (const auto& [name, bytes] : d.upload.bytes)
        if (bytes > 0) parts += fmt::format(" {}={}", name, bytes);
    spdlog::debug(
        "opencl backend: uploaded {} bytes ({} ) in {:.1f} ms (packing {:.1f} ms), {} "
        "meshes with the tracer's own BVH",
        d.upload.total(), parts, timer.milliseconds(), pack_ms, d.own_bvhs);
    return {};
}

namespace {

PfFrameParams frame_params(const RenderJob& job) {
    const FrameSpec& f = job.frame;
    PfFrameParams fp{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            fp.camera_to_world[4 * r + c] = f.camera.camera_to_world[c][r];
    fp.tan_half_fov = std::tan(0.5f * f.camera.yfov_radians);
    fp.width = f.width;
    fp.height = f.height;
    fp.frame = f.frame;
    fp.seed = f.seed;
    fp.spp = std::max(f.spp, 1);
    fp.first_sample = f.first_sample;
    fp.y0 = job.y0;
    fp.y1 = job.y1;
    fp.max_depth = job.integrator.max_depth;
    fp.strategy = int(job.integrator.strategy);
    fp.rr_start_depth = job.integrator.rr_start_depth;
    fp.rr_scale = job.integrator.rr_scale;
    fp.first_hits = job.first_hits != nullptr;
    fp.light_candidates = job.integrator.light_candidates;
    fp.extra_samples = f.extra_samples != nullptr;
    return fp;
}

}  // namespace

// The output and counter buffers grow to the largest row range seen.
Status OpenClBackend::Impl::reserve_output(std::size_t pixels) {
    if (pixels <= out_capacity) return {};
    cl_int err = CL_SUCCESS;
    out = cl::Buffer(shared->context, CL_MEM_WRITE_ONLY, pixels * 3 * sizeof(float), nullptr, &err);
    if (err != CL_SUCCESS) return cl_failure("allocating the output", err);
    counters = cl::Buffer(shared->context, CL_MEM_WRITE_ONLY, pixels * 2 * sizeof(uint32_t),
                          nullptr, &err);
    if (err != CL_SUCCESS) return cl_failure("allocating the counters", err);
    first_hits =
        cl::Buffer(shared->context, CL_MEM_WRITE_ONLY, pixels * sizeof(FirstHit), nullptr, &err);
    if (err != CL_SUCCESS) return cl_failure("allocating the first hits", err);
    extra_samples = cl::Buffer(shared->context, CL_MEM_READ_ONLY, pixels, nullptr, &err);
    if (err != CL_SUCCESS) return cl_failure("allocating the extra samples", err);
    out_capacity = pixels;
    return {};
}

Status OpenClBackend::Impl::set_arguments(cl::Kernel& k, const PfFrameParams& fp) {
    cl_uint arg = 0;
    cl_int err = k.setArg(arg++, sizeof fp, &fp);
#define PF_ARRAY_ARG(name, type) &name,
    for (const DeviceArray* a : {PF_SCENE_ARRAYS(PF_ARRAY_ARG) & globals})
        if (err == CL_SUCCESS) err = k.setArg(arg++, a->buffer());
#undef PF_ARRAY_ARG
    if (err == CL_SUCCESS) err = k.setArg(arg++, out);
    if (err == CL_SUCCESS) err = k.setArg(arg++, counters);
    if (err == CL_SUCCESS) err = k.setArg(arg++, first_hits);
    if (err == CL_SUCCESS) err = k.setArg(arg++, extra_samples);
    if (err != CL_SUCCESS) return cl_failure("setting kernel arguments", err);
    return {};
}

// Launches the kernel over width x rows pixels and reads back the colours, the counters and,
// when wanted, the first hits.
Result<SampleCounters> OpenClBackend::Impl::launch(cl::Kernel& k, int width, std::size_t rows,
                                                   float* pixels_out, FirstHit* hits_out) {
    // A fixed work-group size: PoCL compiles a work-group function per local size, so leaving
    // the choice to the driver compiled again (0.9 s) for every new image width, a stall each
    // time workload scaling changes the resolution; 8x1 measured as fast as the driver's choice.
    constexpr std::size_t kGroupWidth = 8;
    const std::size_t gx = (std::size_t(width) + kGroupWidth - 1) / kGroupWidth * kGroupWidth;
    const std::size_t pixels = rows * std::size_t(width);
    cl_int err = queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(gx, rows),
                                            cl::NDRange(kGroupWidth, 1));
    if (err != CL_SUCCESS) return cl_failure("launching pf_render_rows", err);
    err = queue.enqueueReadBuffer(out, CL_TRUE, 0, pixels * 3 * sizeof(float), pixels_out);
    if (err != CL_SUCCESS) return cl_failure("reading the rendered rows", err);
    if (hits_out) {
        err = queue.enqueueReadBuffer(first_hits, CL_TRUE, 0, pixels * sizeof(FirstHit), hits_out);
        if (err != CL_SUCCESS) return cl_failure("reading the first hits", err);
    }
    counter_host.resize(pixels * 2);
    err = queue.enqueueReadBuffer(counters, CL_TRUE, 0, pixels * 2 * sizeof(uint32_t),
                                  counter_host.data());
    if (err != CL_SUCCESS) return cl_failure("reading the counters", err);
    SampleCounters c;
    for (std::size_t i = 0; i < pixels; ++i) {
        c.rays += counter_host[2 * i];
        c.nonfinite_samples += counter_host[2 * i + 1];
    }
    return c;
}

// The job's rows of its extra-sample map, when it has one.
Status OpenClBackend::Impl::upload_extra_samples(const RenderJob& job) {
    const FrameSpec& f = job.frame;
    if (!f.extra_samples) return {};
    const std::size_t first = std::size_t(job.y0) * std::size_t(f.width);
    const std::size_t bytes = std::size_t(job.y1 - job.y0) * std::size_t(f.width);
    const cl_int err =
        queue.enqueueWriteBuffer(extra_samples, CL_FALSE, 0, bytes, f.extra_samples + first);
    if (err != CL_SUCCESS) return cl_failure("uploading the extra samples", err);
    return {};
}

Result<RenderStats> OpenClBackend::render_rows(const RenderJob& job, float* out) {
    Impl& d = *impl_;
    const FrameSpec& f = job.frame;
    if (!d.has_scene)
        return make_error(ErrorCode::invalid_argument, "opencl backend: render before set_scene");
    if (f.width <= 0 || f.height <= 0 || job.y0 < 0 || job.y1 > f.height || job.y0 > job.y1)
        return make_error(ErrorCode::invalid_argument,
                          "opencl backend: rows [{}, {}) outside a {}x{} frame", job.y0, job.y1,
                          f.width, f.height);
    RenderStats stats;
    if (job.y0 == job.y1) return stats;
    const Timer timer;
    if (Status s = update_lights(job); !s) return s.error();
    const uint32_t variant = job.integrator.specialise ? d.features : uint32_t(kAllFeatures);
    auto kernel = d.kernel(variant);
    if (!kernel) return kernel.error();
    const std::size_t rows = std::size_t(job.y1 - job.y0);
    if (Status s = d.reserve_output(rows * std::size_t(f.width)); !s) return s.error();
    if (Status s = d.upload_extra_samples(job); !s) return s.error();
    const PfFrameParams fp = frame_params(job);
    if (Status s = d.set_arguments(*kernel, fp); !s) return s.error();
    auto counters = d.launch(*kernel, f.width, rows, out, job.first_hits);
    if (!counters) return counters.error();
    stats.counters = *counters;
    stats.counters.camera_samples = uint64_t(rows) * uint64_t(f.width) * uint64_t(fp.spp);
    if (f.extra_samples)
        for (std::size_t i = std::size_t(job.y0) * f.width; i < std::size_t(job.y1) * f.width; ++i)
            stats.counters.camera_samples += f.extra_samples[i];
    stats.seconds = timer.seconds();
    return stats;
}

// Emitters a closed surface separates from this frame's camera leave the light arrays (as in
// the Embree backend); the arrays are re-packed and diff-uploaded only when that set or the
// light selection changes.
Status OpenClBackend::update_lights(const RenderJob& job) {
    Impl& d = *impl_;
    const Vec3 eye = transform_point(job.frame.camera.camera_to_world, Vec3(0.0f));
    const bool culled_changed = d.culling.update(eye, job.integrator.cull_sealed_lights);
    if (!culled_changed && d.light_selection == job.integrator.light_selection) return {};
    const std::vector<bool>& excluded = d.culling.excluded();
    d.light_selection = job.integrator.light_selection;
    pack_lights(*d.scene, excluded, d.light_selection, d.light_state, &d.light_topology);
    log_light_choice("opencl backend", d.light_selection, d.light_state.light_selection,
                     d.light_state.light_choice, d.light_state.lights.size(), d.light_in_use);
    d.light_in_use = d.light_state.light_selection;
    spdlog::debug(
        "opencl backend: {} emissive instance(s) sealed off from the camera ({} closed "
        "surface(s))",
        std::count(excluded.begin(), excluded.end(), true), d.culling.enclosure_count());
    const std::vector<PfSceneGlobals> globals{d.light_state.globals};
    for (Status s : {d.upload_array("lights", d.lights, d.light_state.lights),
                     d.upload_array("light_guide", d.light_guide, d.light_state.light_guide),
                     d.upload_array("light_nodes", d.light_nodes, d.light_state.light_nodes),
                     d.upload_array("instances", d.instances, d.light_state.instances),
                     d.upload_array("globals", d.globals, globals)})
        if (!s) return s;
    if (const cl_int err = d.queue.finish(); err != CL_SUCCESS)
        return cl_failure("uploading the lights", err);
    return {};
}

Result<std::unique_ptr<OpenClBackend>> make_opencl_backend(const BackendOptions& options) {
    if (options.threads < 0)
        return make_error(ErrorCode::invalid_argument, "--threads {}: must be >= 0",
                          options.threads);
    auto shared = open_shared_device(options);
    if (!shared) return shared.error();
    auto impl = std::make_unique<OpenClBackend::Impl>();
    impl->shared = *shared;
    impl->texture_lod = options.texture_lod;
    cl_int err = CL_SUCCESS;
    impl->queue = cl::CommandQueue(impl->shared->context, impl->shared->device, 0, &err);
    if (err != CL_SUCCESS) return cl_failure("creating a command queue", err);
    spdlog::info("opencl backend on {}", impl->shared->name);
    return std::unique_ptr<OpenClBackend>(new OpenClBackend(std::move(impl)));
}

Result<std::vector<std::string>> list_opencl_devices() {
    auto list = opencl_platforms();
    if (!list) return list.error();
    std::vector<std::string> lines;
    for (std::size_t p = 0; p < list->size(); ++p) {
        std::vector<cl::Device> devices;
        (*list)[p].getDevices(CL_DEVICE_TYPE_ALL, &devices);
        for (std::size_t d = 0; d < devices.size(); ++d)
            lines.push_back(fmt::format("{}.{} {}: {} ({} compute units, {})", p, d,
                                        (*list)[p].getInfo<CL_PLATFORM_NAME>(),
                                        devices[d].getInfo<CL_DEVICE_NAME>(),
                                        devices[d].getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>(),
                                        devices[d].getInfo<CL_DEVICE_VERSION>()));
    }
    return lines;
}

}  // namespace pathfarm::tracer
