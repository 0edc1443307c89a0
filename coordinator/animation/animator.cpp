// Clip application: sample each channel, write node TRS / weights, re-flatten.
#include "coordinator/animation/animator.h"

#include <charconv>
#include <cmath>

#include "common/math/transform.h"
#include "coordinator/animation/keyframe_track.h"

namespace pathfarm::coord {

Result<int> find_clip(const SceneModel& scene, const std::string& name_or_index) {
    for (std::size_t i = 0; i < scene.animations.size(); ++i)
        if (scene.animations[i].name == name_or_index) return int(i);
    int index = -1;
    const auto [ptr, ec] =
        std::from_chars(name_or_index.data(), name_or_index.data() + name_or_index.size(), index);
    if (ec == std::errc() && ptr == name_or_index.data() + name_or_index.size() && index >= 0 &&
        index < int(scene.animations.size()))
        return index;
    return make_error(ErrorCode::invalid_argument, "--clip {}: no such animation ({} in the scene)",
                      name_or_index, scene.animations.size());
}

void apply_clip(SceneModel& scene, int clip_index, float t) {
    const AnimationClip& clip = scene.animations.at(std::size_t(clip_index));
    float v[4];
    for (const AnimationChannel& ch : clip.channels) {
        const AnimationSampler& s = clip.samplers[ch.sampler];
        Node& node = scene.nodes[ch.node];
        switch (ch.path) {
            case AnimationPath::translation:
                sample_keyframes(s, t, 3, false, v);
                node.translation = Vec3(v[0], v[1], v[2]);
                break;
            case AnimationPath::rotation:
                sample_keyframes(s, t, 4, true, v);
                node.rotation = glm::quat(v[3], v[0], v[1], v[2]);
                break;
            case AnimationPath::scale:
                sample_keyframes(s, t, 3, false, v);
                node.scale = Vec3(v[0], v[1], v[2]);
                break;
            case AnimationPath::weights: {
                const std::size_t keys =
                    s.times.size() * (s.interpolation == Interpolation::cubic_spline ? 3 : 1);
                node.morph_weights.resize(s.values.size() / keys);
                sample_keyframes(s, t, int(node.morph_weights.size()), false,
                                 node.morph_weights.data());
                break;
            }
        }
    }
    for (Node& node : scene.nodes)
        if (node.has_trs) node.local = compose_trs(node.translation, node.rotation, node.scale);
    flatten_nodes(scene);
}

float looped_clip_time(const AnimationClip& clip, double clock_seconds) {
    const double length = double(clip.end_time) - double(clip.start_time);
    if (!(length > 0.0)) return clip.start_time;
    return float(double(clip.start_time) + std::fmod(std::max(clock_seconds, 0.0), length));
}

}  // namespace pathfarm::coord
