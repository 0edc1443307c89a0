// Reading glTF accessors (strided, normalised, sparse) into flat arrays, with bounds checks,
// so that a truncated or malformed buffer is an error rather than a read past the end.
#pragma once

#include <cstdint>
#include <vector>

#include "common/base/result.h"

namespace tinygltf {
class Model;
}

namespace pathfarm {

// Reads accessor `index` as floats: count * components values, normalised integers mapped to
// [0,1] or [-1,1] as the glTF spec says.
Status read_accessor_floats(const tinygltf::Model& model, int index, std::vector<float>& out,
                            int& components);
// Reads an index (or joint) accessor of unsigned integers.
Status read_accessor_uints(const tinygltf::Model& model, int index, std::vector<uint32_t>& out);

}  // namespace pathfarm
