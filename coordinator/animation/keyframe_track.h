// Sampling glTF keyframe curves (glTF 2.0, "Animations" and Appendix C "Interpolation").
#pragma once

#include "common/scene/animation.h"

namespace pathfarm::coord {

// Evaluates `sampler` at time t (the clip's own sampler time; before the first key the first
// value holds, after the last key the last). Writes `count` floats to out, where count is
// components for T/R/S and the number of morph targets for weights. rotation selects
// shortest-path slerp for LINEAR and normalisation of the result.
void sample_keyframes(const AnimationSampler& sampler, float t, int count, bool rotation,
                      float* out);

// Shortest-path spherical linear interpolation of unit quaternions stored x, y, z, w.
void slerp(const float* q0, const float* q1, double u, float* out);

}  // namespace pathfarm::coord
