// The OpenCL device a backend renders on: platform and device selection, the context and the
// programs built for it. Shared by every backend of the process that opens the same device,
// so kernels compile once per process and feature variant. Internal to the OpenCL backend
// (it includes CL/opencl.hpp).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <CL/opencl.hpp>

#include "common/base/result.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::tracer {

// "opencl backend: <what>: CL_..." as a backend_error.
Error cl_failure(const std::string& what, cl_int code);

struct SharedDevice {
    cl::Device device;
    cl::Context context;
    std::string name;

    // The program for this feature variant (PF_FEATURES), built on first use.
    Result<cl::Program> program(uint32_t features);

private:
    std::mutex mutex_;
    std::map<uint32_t, cl::Program> programs_;  // by feature variant
};

// The installed platforms; fails with a hint to install a driver when there is none.
Result<std::vector<cl::Platform>> opencl_platforms();

// Device options.cl_device of platform options.cl_platform, split to options.threads
// compute units where the device supports it; the same device and split share one instance.
Result<std::shared_ptr<SharedDevice>> open_shared_device(const BackendOptions& options);

}  // namespace pathfarm::tracer
