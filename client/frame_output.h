// Received frames: decoded for showing (sRGB bytes, and the linear pixels of lossless float
// frames) and written to --out as they came (the coordinator's JPEG/PNG bytes, EXR for float
// frames, PNG plus the playable stream.h264 for H.264).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "client/client.h"
#include "common/base/result.h"
#include "common/film/film.h"
#include "common/wire/messages.h"

namespace pathfarm {
class H264Decoder;
}

namespace pathfarm::client {

struct DecodedFrame {
    int width = 0, height = 0;
    std::vector<uint8_t> srgb8;
    std::optional<FloatImage> linear;
};

// `video`: the H.264 stream's decoder (each picture depends on the ones before).
Result<DecodedFrame> decode_image(const wire::EncodedFrame& f, H264Decoder& video);
Status write_frame(const ClientOptions& o, const wire::EncodedFrame& f, const DecodedFrame& d);

}  // namespace pathfarm::client
