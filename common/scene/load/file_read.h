// Whole-file reads that transparently decompress gzip (.obj.gz, .ply.gz) through zlib.
#pragma once

#include <string>

#include "common/base/result.h"

namespace pathfarm {

// Returns the file's bytes, gunzipped when the file is gzip-compressed. A truncated or corrupt
// gzip stream is an error naming the file.
Result<std::string> read_file_maybe_gzip(const std::string& path);

}  // namespace pathfarm
