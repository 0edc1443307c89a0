// The browser client's WebSocket messages: inputs from browsers (untrusted) and frame headers.
#include <string_view>

#include "coordinator/http/web_protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    (void)pathfarm::coord::decode_web_input(bytes);
    (void)pathfarm::coord::decode_web_frame_header(bytes);
    return 0;
}
