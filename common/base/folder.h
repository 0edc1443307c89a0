// Creating an output folder a process was given on its command line.
#pragma once

#include <string>
#include <string_view>

#include "common/base/result.h"

namespace pathfarm {

// Creates `path` and its parents unless they exist. Fails with "<option> <path>: cannot create
// the folder (<reason>)" (std::filesystem's throwing form ended the process from an uncaught
// exception), or "...: not a folder" where a file of that name is in the way.
Status create_output_folder(std::string_view option, const std::string& path);

}  // namespace pathfarm
