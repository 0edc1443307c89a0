// The wire form of a frame's extra-sample map (FrameSpec::extra_samples,
// FrameAssignment.extra_samples_zstd): a byte per pixel, zstd-compressed. The map is mostly
// zeros and a repeating dither, so a 320x180 frame's is a few hundred bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/base/result.h"

namespace pathfarm {

// At most this many samples beyond spp for one pixel (a tracer refuses more).
inline constexpr uint8_t kMaxExtraSamples = 15;

std::string encode_extra_samples(const std::vector<uint8_t>& map);
// Fails unless `data` holds exactly width x height bytes, each at most kMaxExtraSamples.
Result<std::vector<uint8_t>> decode_extra_samples(const std::string& data, int width, int height);

}  // namespace pathfarm
