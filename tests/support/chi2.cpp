// Chi-square test implementation.
#include "tests/support/chi2.h"

#include <cmath>
#include <vector>

#include "common/sampling/rng.h"

namespace pathfarm::test {
namespace {

Vec3 direction(double cos_theta, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    return Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(cos_theta));
}

}  // namespace

double chi2_p_value(double x, int k) {
    if (k <= 0) return 1.0;
    const double z = (std::cbrt(x / k) - (1.0 - 2.0 / (9.0 * k))) / std::sqrt(2.0 / (9.0 * k));
    return 0.5 * std::erfc(z / std::sqrt(2.0));
}

double integrate_sphere(const std::function<float(const Vec3&)>& pdf, int n) {
    double sum = 0.0;
    const double dc = 2.0 / n, dp = 2.0 * M_PI / (2 * n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 2 * n; ++j)
            sum += pdf(direction(-1.0 + (i + 0.5) * dc, (j + 0.5) * dp));
    return sum * dc * dp;
}

Chi2Result chi2_directions(const std::function<bool(float, Vec2, Vec3&)>& sample,
                           const std::function<float(const Vec3&)>& pdf, int sample_count,
                           uint64_t seed, int theta_bins, int phi_bins) {
    const int bins = theta_bins * phi_bins;
    std::vector<double> observed(bins + 1, 0.0), expected(bins + 1, 0.0);
    Pcg32 rng(seed);
    for (int s = 0; s < sample_count; ++s) {
        Vec3 w;
        if (!sample(rng.next_float(), rng.next_2d(), w) || !is_finite(w)) {
            observed[bins] += 1.0;
            continue;
        }
        const int t = std::clamp(int((w.z + 1.0f) * 0.5f * theta_bins), 0, theta_bins - 1);
        double phi = std::atan2(double(w.y), double(w.x));
        if (phi < 0.0) phi += 2.0 * M_PI;
        const int p = std::clamp(int(phi / (2.0 * M_PI) * phi_bins), 0, phi_bins - 1);
        observed[t * phi_bins + p] += 1.0;
    }
    constexpr int kSub = 24;  // sub-samples per bin side for the numerical integral
    double total = 0.0;
    for (int t = 0; t < theta_bins; ++t)
        for (int p = 0; p < phi_bins; ++p) {
            const double c0 = -1.0 + 2.0 * t / theta_bins, dc = 2.0 / theta_bins / kSub;
            const double p0 = 2.0 * M_PI * p / phi_bins, dp = 2.0 * M_PI / phi_bins / kSub;
            double integral = 0.0;
            for (int a = 0; a < kSub; ++a)
                for (int b = 0; b < kSub; ++b)
                    integral += pdf(direction(c0 + (a + 0.5) * dc, p0 + (b + 0.5) * dp));
            integral *= dc * dp;
            expected[t * phi_bins + p] = integral * sample_count;
            total += integral;
        }
    expected[bins] = std::max(0.0, 1.0 - total) * sample_count;
    // Pool bins with small expectations (the usual rule: expected >= 5).
    Chi2Result r;
    double pooled_obs = 0.0, pooled_exp = 0.0;
    for (int i = 0; i <= bins; ++i) {
        if (expected[i] < 5.0) {
            pooled_obs += observed[i];
            pooled_exp += expected[i];
            continue;
        }
        r.statistic += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++r.dof;
    }
    if (pooled_exp >= 5.0) {
        r.statistic += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        ++r.dof;
    } else if (pooled_obs > 5.0 + 5.0 * pooled_exp) {
        r.statistic += 1e9;  // samples landed where the pdf says they cannot
    }
    r.dof -= 1;
    r.p_value = chi2_p_value(r.statistic, r.dof);
    return r;
}

}  // namespace pathfarm::test
