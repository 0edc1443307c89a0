// The loaders read files: a fuzz input goes to a file of this process's own (on tmpfs where
// there is one) with the extension the loader dispatches on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace pathfarm::fuzz {

// Writes the bytes to the process's input file ending in `extension` and returns its path.
std::string write_input_file(const uint8_t* data, std::size_t size, const std::string& extension);

}  // namespace pathfarm::fuzz
