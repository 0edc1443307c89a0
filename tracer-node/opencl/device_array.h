// A device buffer that mirrors a host array. assign() writes only the elements that differ
// from what the device holds (runs of changed elements), so a commit that moves one instance
// uploads that instance's record, not the scene. Internal to the OpenCL backend.
#pragma once

#include <cstddef>
#include <vector>

#include <CL/opencl.hpp>

#include "common/base/result.h"

namespace pathfarm::tracer {

class DeviceArray {
public:
    // Makes the device buffer hold `size` bytes of `data`, compared in `element`-byte records.
    // Returns the number of bytes written. The writes are asynchronous: the mirror stays
    // untouched until the next assign, which the caller makes after the queue finished.
    Result<std::size_t> assign(const cl::Context& context, cl::CommandQueue& queue,
                               const void* data, std::size_t size, std::size_t element);
    const cl::Buffer& buffer() const { return buffer_; }

private:
    Result<std::size_t> reallocate(const cl::Context& context, cl::CommandQueue& queue,
                                   const unsigned char* bytes, std::size_t size);
    cl::Buffer buffer_;
    std::size_t capacity_ = 0;
    std::vector<unsigned char> mirror_;
};

}  // namespace pathfarm::tracer
