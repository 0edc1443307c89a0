// An EncodedFrame as a client receives it.
#include <string>

#include "common/wire/messages.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    (void)pathfarm::wire::decode_frame(std::string(reinterpret_cast<const char*>(data), size));
    return 0;
}
