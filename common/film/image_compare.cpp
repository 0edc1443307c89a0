// RMSE and relative MSE.
#include "common/film/image_compare.h"

#include "common/base/check.h"

namespace pathfarm {

double rmse(const FloatImage& a, const FloatImage& reference) {
    PF_CHECK_EQ(a.rgb.size(), reference.rgb.size());
    double sum = 0.0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
        const double d = double(a.rgb[i]) - reference.rgb[i];
        sum += d * d;
    }
    return a.rgb.empty() ? 0.0 : std::sqrt(sum / double(a.rgb.size()));
}

double relative_mse(const FloatImage& a, const FloatImage& reference, double eps) {
    PF_CHECK_EQ(a.rgb.size(), reference.rgb.size());
    double sum = 0.0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
        const double r = reference.rgb[i];
        const double d = double(a.rgb[i]) - r;
        sum += d * d / (r * r + eps);
    }
    return a.rgb.empty() ? 0.0 : sum / double(a.rgb.size());
}

}  // namespace pathfarm
