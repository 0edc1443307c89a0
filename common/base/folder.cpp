#include "common/base/folder.h"

#include <filesystem>
#include <system_error>

namespace pathfarm {

Status create_output_folder(std::string_view option, const std::string& path) {
    std::error_code error;
    std::filesystem::create_directories(path, error);
    if (error)
        return make_error(ErrorCode::io_error, "{} {}: cannot create the folder ({})", option, path,
                          error.message());
    if (!std::filesystem::is_directory(path, error))
        return make_error(ErrorCode::io_error, "{} {}: not a folder", option, path);
    return {};
}

}  // namespace pathfarm
