// Message framing: any 4-byte header with any limit is a length within the limit or an error.
#include <cstdlib>
#include <string>

#include "common/net/framing.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size < 8) return 0;
    uint32_t limit = 0;
    for (int i = 0; i < 4; ++i)
        limit = (limit << 8) | data[4 + i];
    const auto n = pathfarm::net::read_frame_header(data, limit);
    if (n && (*n == 0 || *n > limit)) std::abort();
    const std::string framed =
        pathfarm::net::frame(std::string(reinterpret_cast<const char*>(data) + 8, size - 8));
    if (size > 8) {
        const auto back = pathfarm::net::read_frame_header(
            reinterpret_cast<const unsigned char*>(framed.data()), uint32_t(size));
        if (!back || *back != size - 8) std::abort();  // the header says what follows it
    }
    return 0;
}
