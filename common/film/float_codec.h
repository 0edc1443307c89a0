// Lossless compression of linear float32 pixel rows (tiles, float frames) with zstd.
#pragma once

#include <string>
#include <vector>

#include "common/base/result.h"

namespace pathfarm {

std::string compress_floats(const float* values, std::size_t count, int level = 1);
// Fails unless the data decompresses to exactly expected_count floats.
Result<std::vector<float>> decompress_floats(const std::string& data, std::size_t expected_count);

}  // namespace pathfarm
