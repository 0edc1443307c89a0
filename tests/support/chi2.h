// Chi-square goodness-of-fit test of a direction sampler against its claimed density
// (the pbrt/Mitsuba approach): histogram sampled directions over (cos theta, phi) bins,
// compare with the density integrated numerically over each bin.
#pragma once

#include <functional>

#include "common/math/types.h"

namespace pathfarm::test {

struct Chi2Result {
    double statistic = 0.0;
    int dof = 0;
    double p_value = 1.0;
};

// sample(u1, u2, u3, wi) returns false when no direction is produced; pdf(wi) is per solid
// angle. Failed samples form one extra bin whose expectation is 1 - integral of the pdf.
Chi2Result chi2_directions(const std::function<bool(float, Vec2, Vec3&)>& sample,
                           const std::function<float(const Vec3&)>& pdf, int sample_count,
                           uint64_t seed, int theta_bins = 12, int phi_bins = 24);

// Integral of pdf over the sphere (midpoint rule on a fine grid).
double integrate_sphere(const std::function<float(const Vec3&)>& pdf, int n = 400);

// Upper tail of the chi-square distribution (Wilson–Hilferty normal approximation).
double chi2_p_value(double statistic, int dof);

}  // namespace pathfarm::test
