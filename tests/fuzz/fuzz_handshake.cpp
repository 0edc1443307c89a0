// The handshake's envelopes, as the first bytes any peer sends.
#include <string>

#include "common/net/handshake.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    (void)pathfarm::net::decode_handshake(std::string(reinterpret_cast<const char*>(data), size));
    return 0;
}
