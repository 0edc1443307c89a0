// A tracer's Tile as the coordinator handles it: the envelope, then its compressed colours and
// first hits for a tile width taken from the input.
#include <algorithm>
#include <string>

#include "common/film/first_hits.h"
#include "common/film/float_codec.h"
#include "common/wire/messages.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const std::size_t width = 1 + data[0] % 64;
    const auto tile =
        pathfarm::wire::decode_tile(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
    if (!tile) return 0;
    const std::size_t pixels = width * std::min<std::size_t>(tile->y1 - tile->y0, 64);
    (void)pathfarm::decompress_floats(tile->rgb_zstd, pixels * 3);
    (void)pathfarm::decode_first_hits(tile->first_hits_zstd, pixels);
    return 0;
}
