// Animation data of a scene as glTF 2.0 defines it: keyframe clips targeting node TRS and morph
// weights, and skins. Evaluation lives in coordinator/animation (the coordinator owns time).
#pragma once

#include <string>
#include <vector>

#include "common/math/types.h"

namespace pathfarm {

enum class AnimationPath : uint8_t { translation, rotation, scale, weights };
enum class Interpolation : uint8_t { step, linear, cubic_spline };

// One keyframe curve. values holds `components` floats per key, or three times that for
// cubic_spline (in-tangent, value, out-tangent per key, as glTF stores them). Rotations are
// quaternions x, y, z, w.
struct AnimationSampler {
    std::vector<float> times;  // seconds, strictly increasing
    std::vector<float> values;
    int components = 0;
    Interpolation interpolation = Interpolation::linear;
};

struct AnimationChannel {
    int node = -1;  // index into SceneModel::nodes
    AnimationPath path = AnimationPath::translation;
    int sampler = -1;  // index into AnimationClip::samplers
};

struct AnimationClip {
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    float start_time = 0.0f;  // first and last key over all samplers
    float end_time = 0.0f;
};

// glTF skin: joint matrix j = world(joint j) * inverse_bind[j]; the skinned mesh's own node
// transform is ignored (glTF 2.0, "Skins").
struct Skin {
    std::string name;
    std::vector<int> joints;  // indices into SceneModel::nodes
    std::vector<Mat4> inverse_bind;
};

}  // namespace pathfarm
