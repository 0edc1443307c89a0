// Encoding assembled frames for clients: tonemapped and sRGB-encoded here on the coordinator,
// then JPEG (the default: small and fast) or PNG, or lossless zstd float32.
#pragma once

#include <string>

#include "common/base/result.h"
#include "common/film/film.h"
#include "common/wire/frame_codec.h"

namespace pathfarm::coord {

using wire::FrameCodec;

Result<std::string> encode_frame(const FloatImage& image, FrameCodec codec, int jpeg_quality = 90);
// Picks the first codec of a client's list that this coordinator can encode (default JPEG).
FrameCodec choose_codec(const std::vector<int>& accepted);

}  // namespace pathfarm::coord
