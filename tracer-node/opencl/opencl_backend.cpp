// OpenClBackend: device selection, the per-process program cache, buffers updated by diff,
// and the row-range launch.
#include "tracer-node/opencl/opencl_backend.h"

#include <cstring>
#include <mutex>

#include <spdlog/spdlog.h>
#include <CL/opencl.hpp>

#include "common/base/timer.h"
#include "common/math/transform.h"
#include "common/render/sealed_emitters.h"
#include "tracer-node/opencl/cl_errors.h"
#include "tracer-node/opencl/device_scene.h"

namespace pathfarm::tracer {

extern const char* const kOpenClKernelSource;  // generated from kernels/ at build time

namespace {

Error cl_failure(const std::string& what, cl_int code) {
    return Error{ErrorCode::backend_error,
                 fmt::format("opencl backend: {}: {}", what, cl_error_name(code))};
}

// A device with its context and the programs built for it, shared by every backend of the
// process that uses the same device: kernels compile once per process and variant.
struct SharedDevice {
    cl::Device device;
    cl::Context context;
    std::string name;
    std::mutex mutex;
    std::map<uint32_t, cl::Program> programs;  // by feature variant

    Result<cl::Program> program(uint32_t features) {
        const std::lock_guard lock(mutex);
        if (auto it = programs.find(features); it != programs.end()) return it->second;
        const Timer timer;
        cl_int err = CL_SUCCESS;
        cl::Program program(context, std::string(kOpenClKernelSource), false, &err);
        if (err != CL_SUCCESS) return cl_failure("creating the program", err);
        const std::string options = fmt::format("-cl-std=CL1.2 -DPF_FEATURES={}u", features);
        err = program.build(std::vector<cl::Device>{device}, options.c_str());
        if (err != CL_SUCCESS) {
            std::string log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
            spdlog::error("OpenCL build log:\n{}", log);
            if (const auto nl = log.find('\n'); nl != std::string::npos) log.resize(nl);
            return Error{ErrorCode::backend_error,
                         fmt::format("opencl backend: building the kernels for {}: {}: {}", name,
                                     cl_error_name(err), log)};
        }
        spdlog::info("OpenCL kernels (features {}) built for {} in {:.2f} s", features, name,
                     timer.seconds());
        programs.emplace(features, program);
        return program;
    }
};

Result<std::vector<cl::Platform>> platforms() {
    std::vector<cl::Platform> list;
    const cl_int err = cl::Platform::get(&list);
    if (err == CL_PLATFORM_NOT_FOUND_KHR || (err == CL_SUCCESS && list.empty()))
        return make_error(ErrorCode::unsupported,
                          "opencl backend: no OpenCL platform found (install an OpenCL driver, "
                          "e.g. apt-get install pocl-opencl-icd)");
    if (err != CL_SUCCESS) return cl_failure("listing platforms", err);
    return list;
}

Result<std::shared_ptr<SharedDevice>> open_shared_device(const BackendOptions& o) {
    static std::mutex mutex;
    static std::map<std::tuple<int, int, cl_uint>, std::shared_ptr<SharedDevice>> devices;
    const std::lock_guard lock(mutex);
    auto list = platforms();
    if (!list) return list.error();
    if (o.cl_platform < 0 || std::size_t(o.cl_platform) >= list->size())
        return make_error(ErrorCode::invalid_argument,
                          "--cl-platform {}: out of range ({} OpenCL platform(s))", o.cl_platform,
                          list->size());
    const cl::Platform& platform = (*list)[std::size_t(o.cl_platform)];
    std::vector<cl::Device> found;
    cl_int err = platform.getDevices(CL_DEVICE_TYPE_ALL, &found);
    if (err != CL_SUCCESS && err != CL_DEVICE_NOT_FOUND) return cl_failure("listing devices", err);
    if (o.cl_device < 0 || std::size_t(o.cl_device) >= found.size())
        return make_error(ErrorCode::invalid_argument,
                          "--cl-device {}: out of range (platform {} has {} device(s))",
                          o.cl_device, o.cl_platform, found.size());
    const cl::Device& device = found[std::size_t(o.cl_device)];
    const cl_uint units = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
    const cl_uint wanted = o.threads > 0 && cl_uint(o.threads) < units ? cl_uint(o.threads) : 0;
    const auto key = std::make_tuple(o.cl_platform, o.cl_device, wanted);
    if (auto it = devices.find(key); it != devices.end()) return it->second;

    auto shared = std::make_shared<SharedDevice>();
    shared->device = device;
    shared->name = shared->device.getInfo<CL_DEVICE_NAME>();
    // --threads: a sub-device with that many compute units (device fission), where supported.
    if (wanted > 0) {
        const cl_device_partition_property props[] = {CL_DEVICE_PARTITION_EQUALLY,
                                                      cl_device_partition_property(wanted), 0};
        std::vector<cl::Device> sub;
        if (shared->device.createSubDevices(props, &sub) == CL_SUCCESS && !sub.empty())
            shared->device = sub.front();
        else
            spdlog::warn("opencl backend: {} cannot be split into {} compute units; using all {}",
                         shared->name, o.threads, units);
    }
    shared->context = cl::Context(shared->device, nullptr, nullptr, nullptr, &err);
    if (err != CL_SUCCESS) return cl_failure("creating a context on " + shared->name, err);
    devices.emplace(key, shared);
    return shared;
}

// A device buffer that mirrors a host array. assign() writes only the elements that differ
// from what the device holds (runs of changed elements), so a commit that moves one instance
// uploads that instance's record, not the scene.
class DeviceArray {
public:
    // Returns the number of bytes written. The write is asynchronous: mirror_ stays untouched
    // until the next assign, after the queue finished.
    Result<std::size_t> assign(const cl::Context& context, cl::CommandQueue& queue,
                               const void* data, std::size_t size, std::size_t element) {
        const auto* bytes = static_cast<const unsigned char*>(data);
        if (size > capacity_ || !buffer_()) {
            const std::size_t capacity =
                std::max<std::size_t>({size, capacity_ + capacity_ / 2, 64});
            cl_int err = CL_SUCCESS;
            cl::Buffer buffer(context, CL_MEM_READ_ONLY, capacity, nullptr, &err);
            if (err != CL_SUCCESS)
                return cl_failure(fmt::format("allocating {} bytes", capacity), err);
            buffer_ = buffer;
            capacity_ = capacity;
            mirror_.assign(bytes, bytes + size);
            if (size > 0) {
                err = queue.enqueueWriteBuffer(buffer_, CL_FALSE, 0, size, mirror_.data());
                if (err != CL_SUCCESS) return cl_failure("uploading", err);
            }
            return size;
        }
        std::size_t written = 0;
        const std::size_t old_size = mirror_.size();
        mirror_.resize(size);
        std::size_t run_start = 0;
        bool in_run = false;
        auto flush = [&](std::size_t end) -> cl_int {
            in_run = false;
            written += end - run_start;
            return queue.enqueueWriteBuffer(buffer_, CL_FALSE, run_start, end - run_start,
                                            mirror_.data() + run_start);
        };
        // Whole blocks that match are skipped with one memcmp; only differing blocks are
        // compared element by element.
        const std::size_t block = element * std::max<std::size_t>(1, 4096 / element);
        for (std::size_t off = 0; off < size; off += element) {
            if (off % block == 0 && off + block <= std::min(size, old_size) &&
                std::memcmp(mirror_.data() + off, bytes + off, block) == 0) {
                if (in_run)
                    if (cl_int err = flush(off); err != CL_SUCCESS)
                        return cl_failure("uploading", err);
                off += block - element;
                continue;
            }
            const std::size_t n = std::min(element, size - off);
            const bool changed =
                off + n > old_size || std::memcmp(mirror_.data() + off, bytes + off, n) != 0;
            if (changed) {
                std::memcpy(mirror_.data() + off, bytes + off, n);
                if (!in_run) {
                    in_run = true;
                    run_start = off;
                }
            } else if (in_run) {
                if (cl_int err = flush(off); err != CL_SUCCESS) return cl_failure("uploading", err);
            }
        }
        if (in_run)
            if (cl_int err = flush(size); err != CL_SUCCESS) return cl_failure("uploading", err);
        return written;
    }
    const cl::Buffer& buffer() const { return buffer_; }

private:
    cl::Buffer buffer_;
    std::size_t capacity_ = 0;
    std::vector<unsigned char> mirror_;
};

}  // namespace

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
    // Scene buffers (device_types.h PF_SCENE_ARRAYS), then the globals.
#define PF_DEVICE_ARRAY(name, type) DeviceArray name;
    PF_SCENE_ARRAYS(PF_DEVICE_ARRAY)
#undef PF_DEVICE_ARRAY
    DeviceArray globals;
    std::map<uint32_t, cl::Kernel> kernels;  // by variant
    cl::Buffer out, counters;
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
};

OpenClBackend::OpenClBackend(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OpenClBackend::~OpenClBackend() = default;

void OpenClBackend::provide_mesh_bvhs(std::vector<MeshBvhView> bvhs) {
    impl_->provided_bvhs = std::move(bvhs);
}

const UploadStats& OpenClBackend::last_upload() const { return impl_->upload; }
std::size_t OpenClBackend::meshes_with_own_bvh() const { return impl_->own_bvhs; }
std::string OpenClBackend::device_name() const { return impl_->shared->name; }

Status OpenClBackend::set_scene(const SceneModel& scene) {
    Impl& d = *impl_;
    const Timer timer;
    const PackedScene p = pack_scene(scene, d.provided_bvhs, d.bvh_cache);
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
    std::string parts;
    for (const auto& [name, bytes] : d.upload.bytes)
        if (bytes > 0) parts += fmt::format(" {}={}", name, bytes);
    spdlog::debug(
        "opencl backend: uploaded {} bytes ({} ) in {:.1f} ms (packing {:.1f} ms), {} "
        "meshes with the tracer's own BVH",
        d.upload.total(), parts, timer.milliseconds(), pack_ms, d.own_bvhs);
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
    const std::size_t pixels = rows * std::size_t(f.width);
    cl_int err = CL_SUCCESS;
    if (pixels > d.out_capacity) {
        d.out = cl::Buffer(d.shared->context, CL_MEM_WRITE_ONLY, pixels * 3 * sizeof(float),
                           nullptr, &err);
        if (err != CL_SUCCESS) return cl_failure("allocating the output", err);
        d.counters = cl::Buffer(d.shared->context, CL_MEM_WRITE_ONLY, pixels * 2 * sizeof(uint32_t),
                                nullptr, &err);
        if (err != CL_SUCCESS) return cl_failure("allocating the counters", err);
        d.out_capacity = pixels;
    }
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

    cl::Kernel& k = *kernel;
    cl_uint arg = 0;
    err = k.setArg(arg++, sizeof fp, &fp);
#define PF_ARRAY_ARG(name, type) &d.name,
    for (const DeviceArray* a : {PF_SCENE_ARRAYS(PF_ARRAY_ARG) & d.globals})
        if (err == CL_SUCCESS) err = k.setArg(arg++, a->buffer());
#undef PF_ARRAY_ARG
    if (err == CL_SUCCESS) err = k.setArg(arg++, d.out);
    if (err == CL_SUCCESS) err = k.setArg(arg++, d.counters);
    if (err != CL_SUCCESS) return cl_failure("setting kernel arguments", err);

    // A fixed work-group size: PoCL compiles a work-group function per local size, so leaving
    // the choice to the driver compiled again (0.9 s) for every new image width, a stall each
    // time workload scaling changes the resolution; 8x1 measured as fast as the driver's choice.
    constexpr std::size_t kGroupWidth = 8;
    const std::size_t gx = (std::size_t(f.width) + kGroupWidth - 1) / kGroupWidth * kGroupWidth;
    err = d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(gx, rows),
                                       cl::NDRange(kGroupWidth, 1));
    if (err != CL_SUCCESS) return cl_failure("launching pf_render_rows", err);
    err = d.queue.enqueueReadBuffer(d.out, CL_TRUE, 0, pixels * 3 * sizeof(float), out);
    if (err != CL_SUCCESS) return cl_failure("reading the rendered rows", err);
    d.counter_host.resize(pixels * 2);
    err = d.queue.enqueueReadBuffer(d.counters, CL_TRUE, 0, pixels * 2 * sizeof(uint32_t),
                                    d.counter_host.data());
    if (err != CL_SUCCESS) return cl_failure("reading the counters", err);
    for (std::size_t i = 0; i < pixels; ++i) {
        stats.counters.rays += d.counter_host[2 * i];
        stats.counters.nonfinite_samples += d.counter_host[2 * i + 1];
    }
    stats.counters.camera_samples = uint64_t(pixels) * uint64_t(fp.spp);
    stats.seconds = timer.seconds();
    return stats;
}

// Emitters a closed surface separates from this frame's camera leave the light arrays (as in
// the Embree backend); the arrays are re-packed and diff-uploaded only when that set changes.
Status OpenClBackend::update_lights(const RenderJob& job) {
    Impl& d = *impl_;
    const Vec3 eye = transform_point(job.frame.camera.camera_to_world, Vec3(0.0f));
    if (!d.culling.update(eye, job.integrator.cull_sealed_lights)) return {};
    const std::vector<bool>& excluded = d.culling.excluded();
    pack_lights(*d.scene, excluded, d.light_state);
    spdlog::debug(
        "opencl backend: {} emissive instance(s) sealed off from the camera ({} closed "
        "surface(s))",
        std::count(excluded.begin(), excluded.end(), true), d.culling.enclosure_count());
    const std::vector<PfSceneGlobals> globals{d.light_state.globals};
    for (Status s : {d.upload_array("lights", d.lights, d.light_state.lights),
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
    cl_int err = CL_SUCCESS;
    impl->queue = cl::CommandQueue(impl->shared->context, impl->shared->device, 0, &err);
    if (err != CL_SUCCESS) return cl_failure("creating a command queue", err);
    spdlog::info("opencl backend on {}", impl->shared->name);
    return std::unique_ptr<OpenClBackend>(new OpenClBackend(std::move(impl)));
}

Result<std::vector<std::string>> list_opencl_devices() {
    auto list = platforms();
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
