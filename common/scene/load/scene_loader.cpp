// Dispatch by scene spec and file extension.
#include "common/scene/load/scene_loader.h"

#include <algorithm>
#include <filesystem>

#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/validate.h"

namespace pathfarm {
namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Result<SceneModel> load_file(const std::string& path) {
    std::string lower = path;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        return make_error(ErrorCode::invalid_argument, "{}: a directory, not a scene file", path);
    if (!std::filesystem::is_regular_file(path, ec))
        return make_error(ErrorCode::not_found, "{}: no such file", path);
    if (ends_with(lower, ".gltf") || ends_with(lower, ".glb")) return load_gltf(path);
    if (ends_with(lower, ".obj") || ends_with(lower, ".obj.gz")) return load_obj(path);
    if (ends_with(lower, ".ply") || ends_with(lower, ".ply.gz")) return load_ply(path);
    return make_error(
        ErrorCode::unsupported,
        "{}: unknown scene format (expected .gltf, .glb, .obj[.gz], .ply[.gz] or builtin:NAME)",
        path);
}

}  // namespace

Result<SceneModel> load_scene(const std::string& spec) {
    constexpr std::string_view kBuiltin = "builtin:";
    Result<SceneModel> scene = spec.rfind(kBuiltin, 0) == 0
                                   ? make_builtin_scene(spec.substr(kBuiltin.size()))
                                   : load_file(spec);
    if (!scene) return scene;
    if (Status s = validate_and_repair(*scene, spec); !s) return s.error();
    return scene;
}

}  // namespace pathfarm
