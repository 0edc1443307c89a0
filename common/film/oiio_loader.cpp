// Finding and loading the OpenImageIO module (oiio_images.h).
#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "common/film/oiio_images.h"

namespace pathfarm {
namespace {

constexpr const char* kModuleName = "libpathfarm_oiio.so";

// Where to look, in order (oiio_images.h).
std::vector<std::string> candidate_paths() {
    if (const char* set = std::getenv("PATHFARM_OIIO_MODULE"); set && *set) return {set};
    std::vector<std::string> paths;
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        paths.push_back((exe.parent_path() / kModuleName).string());
        paths.push_back((exe.parent_path() / ".." / "lib" / "pathfarm" / kModuleName).string());
    }
    paths.push_back(PATHFARM_OIIO_MODULE_BUILD_PATH);
    return paths;
}

Result<const OiioImages*> load_default() {
    std::string tried;
    for (const std::string& path : candidate_paths()) {
        if (!std::filesystem::exists(path)) {
            tried += (tried.empty() ? "" : ", ") + path;
            continue;
        }
        return load_oiio_images(path);  // found: its own error, if any, is the one to report
    }
    return make_error(ErrorCode::not_found,
                      "image I/O module {} not found (tried {}; set PATHFARM_OIIO_MODULE)",
                      kModuleName, tried);
}

}  // namespace

Result<const OiioImages*> load_oiio_images(const std::string& path) {
    // Kept loaded for the life of the process: the table points into it.
    void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!module) {
        const char* why = dlerror();
        return make_error(ErrorCode::not_found, "{}: cannot load the image I/O module ({})", path,
                          why ? why : "unknown error");
    }
    using Entry = const OiioImages* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(module, kOiioImagesSymbol));
    if (!entry)
        return make_error(ErrorCode::unsupported, "{}: not an image I/O module (no {})", path,
                          kOiioImagesSymbol);
    const OiioImages* table = entry();
    if (!table || table->abi != kOiioImagesAbi)
        return make_error(ErrorCode::unsupported,
                          "{}: image I/O module of another build (interface {}, this build {})",
                          path, table ? table->abi : -1, kOiioImagesAbi);
    return table;
}

Result<const OiioImages*> oiio_images() {
    static const Result<const OiioImages*> loaded = load_default();
    return loaded;
}

}  // namespace pathfarm
