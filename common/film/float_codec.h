// Lossless zstd compression of pixel data (tiles, float frames, first hits).
#pragma once

#include <string>
#include <vector>

#include "common/base/result.h"

namespace pathfarm {

std::string compress_bytes(const void* data, std::size_t bytes, int level = 1);
// Decompresses into out; fails unless the data holds exactly `bytes` bytes (checked before
// writing). `what` names the data in the error.
Status decompress_bytes(const std::string& data, void* out, std::size_t bytes, const char* what);

std::string compress_floats(const float* values, std::size_t count, int level = 1);
// Fails unless the data decompresses to exactly expected_count floats.
Result<std::vector<float>> decompress_floats(const std::string& data, std::size_t expected_count);

}  // namespace pathfarm
