// Diff upload: runs of changed records, whole unchanged 4 KiB blocks skipped by one memcmp.
#include "tracer-node/opencl/device_array.h"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>

#include "tracer-node/opencl/cl_device.h"

namespace pathfarm::tracer {

Result<std::size_t> DeviceArray::reallocate(const cl::Context& context, cl::CommandQueue& queue,
                                            const unsigned char* bytes, std::size_t size) {
    const std::size_t capacity = std::max<std::size_t>({size, capacity_ + capacity_ / 2, 64});
    cl_int err = CL_SUCCESS;
    cl::Buffer buffer(context, CL_MEM_READ_ONLY, capacity, nullptr, &err);
    if (err != CL_SUCCESS) return cl_failure(fmt::format("allocating {} bytes", capacity), err);
    buffer_ = buffer;
    capacity_ = capacity;
    mirror_.assign(bytes, bytes + size);
    if (size > 0) {
        err = queue.enqueueWriteBuffer(buffer_, CL_FALSE, 0, size, mirror_.data());
        if (err != CL_SUCCESS) return cl_failure("uploading", err);
    }
    return size;
}

Result<std::size_t> DeviceArray::assign(const cl::Context& context, cl::CommandQueue& queue,
                                        const void* data, std::size_t size, std::size_t element) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    if (size > capacity_ || !buffer_()) return reallocate(context, queue, bytes, size);
    std::size_t written = 0;
    const std::size_t old_size = mirror_.size();
    mirror_.resize(size);
    std::size_t run_start = 0;
    bool in_run = false;
    cl_int err = CL_SUCCESS;
    auto flush = [&](std::size_t end) {
        in_run = false;
        written += end - run_start;
        err = queue.enqueueWriteBuffer(buffer_, CL_FALSE, run_start, end - run_start,
                                       mirror_.data() + run_start);
    };
    const std::size_t block = element * std::max<std::size_t>(1, 4096 / element);
    for (std::size_t off = 0; off < size && err == CL_SUCCESS; off += element) {
        if (off % block == 0 && off + block <= std::min(size, old_size) &&
            std::memcmp(mirror_.data() + off, bytes + off, block) == 0) {
            if (in_run) flush(off);
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
            flush(off);
        }
    }
    if (in_run && err == CL_SUCCESS) flush(size);
    if (err != CL_SUCCESS) return cl_failure("uploading", err);
    return written;
}

}  // namespace pathfarm::tracer
