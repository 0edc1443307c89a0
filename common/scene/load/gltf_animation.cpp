// Skins (joints, inverse bind matrices) and keyframe animations from glTF.
#include "common/scene/load/gltf_animation.h"

#include <spdlog/spdlog.h>
#include <tiny_gltf.h>
#include <glm/gtc/type_ptr.hpp>

#include "common/scene/load/gltf_accessor.h"

namespace pathfarm {
namespace {

Result<AnimationSampler> import_sampler(const tinygltf::Model& gltf,
                                        const tinygltf::AnimationSampler& gs,
                                        const std::string& where) {
    AnimationSampler s;
    int comps = 0;
    if (Status st = read_accessor_floats(gltf, gs.input, s.times, comps); !st || comps != 1)
        return make_error(ErrorCode::parse_error, "{}: input: {}", where,
                          st ? "not SCALAR" : st.error().message);
    if (Status st = read_accessor_floats(gltf, gs.output, s.values, s.components); !st)
        return make_error(ErrorCode::parse_error, "{}: output: {}", where, st.error().message);
    if (gs.interpolation == "STEP")
        s.interpolation = Interpolation::step;
    else if (gs.interpolation == "CUBICSPLINE")
        s.interpolation = Interpolation::cubic_spline;
    else
        s.interpolation = Interpolation::linear;
    if (s.times.empty()) return make_error(ErrorCode::parse_error, "{}: no keyframes", where);
    for (std::size_t k = 1; k < s.times.size(); ++k)
        if (!(s.times[k] > s.times[k - 1]))
            return make_error(ErrorCode::parse_error, "{}: key times must increase (key {})", where,
                              k);
    return s;
}

Result<AnimationPath> parse_path(const std::string& path) {
    if (path == "translation") return AnimationPath::translation;
    if (path == "rotation") return AnimationPath::rotation;
    if (path == "scale") return AnimationPath::scale;
    if (path == "weights") return AnimationPath::weights;
    return make_error(ErrorCode::unsupported, "unknown path \"{}\"", path);
}

// Output values per key: 3 for T/S, 4 for rotation, the morph target count for weights; cubic
// splines store three of those per key.
bool output_fits(const AnimationSampler& s, AnimationPath path) {
    const std::size_t keys =
        s.times.size() * (s.interpolation == Interpolation::cubic_spline ? 3 : 1);
    if (path == AnimationPath::weights) return keys > 0 && s.values.size() % keys == 0;
    const int expected = path == AnimationPath::rotation ? 4 : 3;
    return s.components == expected && s.values.size() == keys * std::size_t(expected);
}

}  // namespace

Status import_skins(const tinygltf::Model& gltf, const std::string& path,
                    const std::vector<int>& node_map, SceneModel& scene) {
    for (std::size_t i = 0; i < gltf.skins.size(); ++i) {
        const tinygltf::Skin& gs = gltf.skins[i];
        Skin skin;
        skin.name = gs.name;
        for (int j : gs.joints) {
            if (j < 0 || j >= int(node_map.size()) || node_map[j] < 0)
                return make_error(ErrorCode::parse_error,
                                  "{}: skin {}: joint node {} is not in the scene", path, i, j);
            skin.joints.push_back(node_map[j]);
        }
        skin.inverse_bind.assign(skin.joints.size(), Mat4(1.0f));
        if (gs.inverseBindMatrices >= 0) {
            std::vector<float> m;
            int comps = 0;
            Status st = read_accessor_floats(gltf, gs.inverseBindMatrices, m, comps);
            if (!st || comps != 16 || m.size() != 16 * skin.joints.size())
                return make_error(ErrorCode::parse_error, "{}: skin {}: inverseBindMatrices: {}",
                                  path, i, st ? "not one MAT4 per joint" : st.error().message);
            for (std::size_t j = 0; j < skin.joints.size(); ++j)
                skin.inverse_bind[j] = glm::make_mat4(&m[16 * j]);
        }
        scene.skins.push_back(std::move(skin));
    }
    return {};
}

Status import_animations(const tinygltf::Model& gltf, const std::string& path,
                         const std::vector<int>& node_map, SceneModel& scene) {
    for (std::size_t a = 0; a < gltf.animations.size(); ++a) {
        const tinygltf::Animation& ga = gltf.animations[a];
        AnimationClip clip;
        clip.name = ga.name.empty() ? "animation" + std::to_string(a) : ga.name;
        const std::string where = fmt::format("{}: animation {} \"{}\"", path, a, clip.name);
        for (std::size_t k = 0; k < ga.samplers.size(); ++k) {
            auto s = import_sampler(gltf, ga.samplers[k], fmt::format("{} sampler {}", where, k));
            if (!s) return s.error();
            clip.samplers.push_back(std::move(*s));
        }
        clip.start_time = kInfinity;
        clip.end_time = -kInfinity;
        for (const tinygltf::AnimationChannel& gc : ga.channels) {
            auto p = parse_path(gc.target_path);
            const int node = gc.target_node >= 0 && gc.target_node < int(node_map.size())
                                 ? node_map[gc.target_node]
                                 : -1;
            if (!p || node < 0 || gc.sampler < 0 || gc.sampler >= int(clip.samplers.size())) {
                spdlog::warn("{}: channel on node {} path \"{}\" ignored", where, gc.target_node,
                             gc.target_path);
                continue;
            }
            const AnimationSampler& s = clip.samplers[gc.sampler];
            if (!output_fits(s, *p))
                return make_error(ErrorCode::parse_error,
                                  "{}: channel on node {}: output size does not match {} keys",
                                  where, gc.target_node, s.times.size());
            if (!scene.nodes[node].has_trs && *p != AnimationPath::weights)
                return make_error(ErrorCode::parse_error,
                                  "{}: node {} has a matrix and cannot be animated", where,
                                  gc.target_node);
            clip.channels.push_back({node, *p, gc.sampler});
            clip.start_time = std::min(clip.start_time, s.times.front());
            clip.end_time = std::max(clip.end_time, s.times.back());
        }
        if (clip.channels.empty()) clip.start_time = clip.end_time = 0.0f;
        scene.animations.push_back(std::move(clip));
    }
    return {};
}

}  // namespace pathfarm
