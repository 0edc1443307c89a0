// Device selection (with fission for --threads) and the per-process program cache.
#include "tracer-node/opencl/cl_device.h"

#include <tuple>

#include <spdlog/spdlog.h>

#include "common/base/timer.h"
#include "tracer-node/opencl/cl_errors.h"

namespace pathfarm::tracer {

extern const char* const kOpenClKernelSource;  // generated from kernels/ at build time

Error cl_failure(const std::string& what, cl_int code) {
    return Error{ErrorCode::backend_error,
                 fmt::format("opencl backend: {}: {}", what, cl_error_name(code))};
}

Result<cl::Program> SharedDevice::program(uint32_t features) {
    const std::lock_guard lock(mutex_);
    if (auto it = programs_.find(features); it != programs_.end()) return it->second;
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
    programs_.emplace(features, program);
    return program;
}

Result<std::vector<cl::Platform>> opencl_platforms() {
    std::vector<cl::Platform> list;
    const cl_int err = cl::Platform::get(&list);
    if (err == CL_PLATFORM_NOT_FOUND_KHR || (err == CL_SUCCESS && list.empty()))
        return make_error(ErrorCode::unsupported,
                          "opencl backend: no OpenCL platform found (install an OpenCL driver, "
                          "e.g. apt-get install pocl-opencl-icd)");
    if (err != CL_SUCCESS) return cl_failure("listing platforms", err);
    return list;
}

namespace {

Result<cl::Device> find_device(const BackendOptions& o) {
    auto list = opencl_platforms();
    if (!list) return list.error();
    if (o.cl_platform < 0 || std::size_t(o.cl_platform) >= list->size())
        return make_error(ErrorCode::invalid_argument,
                          "--cl-platform {}: out of range ({} OpenCL platform(s))", o.cl_platform,
                          list->size());
    const cl::Platform& platform = (*list)[std::size_t(o.cl_platform)];
    std::vector<cl::Device> found;
    const cl_int err = platform.getDevices(CL_DEVICE_TYPE_ALL, &found);
    if (err != CL_SUCCESS && err != CL_DEVICE_NOT_FOUND) return cl_failure("listing devices", err);
    if (o.cl_device < 0 || std::size_t(o.cl_device) >= found.size())
        return make_error(ErrorCode::invalid_argument,
                          "--cl-device {}: out of range (platform {} has {} device(s))",
                          o.cl_device, o.cl_platform, found.size());
    return found[std::size_t(o.cl_device)];
}

// --threads: a sub-device with that many compute units (device fission), where supported.
cl::Device split_device(cl::Device device, cl_uint units, const std::string& name) {
    const cl_device_partition_property props[] = {CL_DEVICE_PARTITION_EQUALLY,
                                                  cl_device_partition_property(units), 0};
    std::vector<cl::Device> sub;
    if (device.createSubDevices(props, &sub) == CL_SUCCESS && !sub.empty()) return sub.front();
    spdlog::warn("opencl backend: {} cannot be split into {} compute units; using all {}", name,
                 units, device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
    return device;
}

}  // namespace

Result<std::shared_ptr<SharedDevice>> open_shared_device(const BackendOptions& o) {
    static std::mutex mutex;
    static std::map<std::tuple<int, int, cl_uint>, std::shared_ptr<SharedDevice>> devices;
    const std::lock_guard lock(mutex);
    auto device = find_device(o);
    if (!device) return device.error();
    const cl_uint units = device->getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
    const cl_uint wanted = o.threads > 0 && cl_uint(o.threads) < units ? cl_uint(o.threads) : 0;
    const auto key = std::make_tuple(o.cl_platform, o.cl_device, wanted);
    if (auto it = devices.find(key); it != devices.end()) return it->second;

    auto shared = std::make_shared<SharedDevice>();
    shared->name = device->getInfo<CL_DEVICE_NAME>();
    shared->device = wanted > 0 ? split_device(*device, wanted, shared->name) : *device;
    cl_int err = CL_SUCCESS;
    shared->context = cl::Context(shared->device, nullptr, nullptr, nullptr, &err);
    if (err != CL_SUCCESS) return cl_failure("creating a context on " + shared->name, err);
    devices.emplace(key, shared);
    return shared;
}

}  // namespace pathfarm::tracer
