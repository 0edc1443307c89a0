// RMSE, relative MSE, SSIM and PSNR.
#include "common/film/image_compare.h"

#include <cmath>
#include <limits>
#include <vector>

#include "common/base/check.h"
#include "common/film/tonemap.h"

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

namespace {

// Luma in [0, 1] of sRGB bytes.
std::vector<double> display_luma(const std::vector<uint8_t>& srgb) {
    std::vector<double> luma(srgb.size() / 3);
    for (std::size_t i = 0; i < luma.size(); ++i)
        luma[i] = (0.299 * srgb[3 * i] + 0.587 * srgb[3 * i + 1] + 0.114 * srgb[3 * i + 2]) / 255.0;
    return luma;
}

// Separable Gaussian blur of `v` (w x h), weights renormalised where the window is clipped.
std::vector<double> gaussian(const std::vector<double>& v, int w, int h) {
    constexpr int kRadius = 5;
    double k[2 * kRadius + 1];
    for (int i = -kRadius; i <= kRadius; ++i)
        k[i + kRadius] = std::exp(-0.5 * i * i / (1.5 * 1.5));
    std::vector<double> tmp(v.size()), out(v.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum = 0.0, weight = 0.0;
            for (int i = std::max(-kRadius, -x); i <= std::min(kRadius, w - 1 - x); ++i) {
                sum += k[i + kRadius] * v[std::size_t(y) * w + x + i];
                weight += k[i + kRadius];
            }
            tmp[std::size_t(y) * w + x] = sum / weight;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum = 0.0, weight = 0.0;
            for (int i = std::max(-kRadius, -y); i <= std::min(kRadius, h - 1 - y); ++i) {
                sum += k[i + kRadius] * tmp[std::size_t(y + i) * w + x];
                weight += k[i + kRadius];
            }
            out[std::size_t(y) * w + x] = sum / weight;
        }
    return out;
}

// SSIM of two luma planes (w x h, values in [0, 1]).
double ssim_of_luma(const std::vector<double>& x, const std::vector<double>& y, int w, int h) {
    std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        xx[i] = x[i] * x[i];
        yy[i] = y[i] * y[i];
        xy[i] = x[i] * y[i];
    }
    const std::vector<double> mx = gaussian(x, w, h), my = gaussian(y, w, h);
    const std::vector<double> sxx = gaussian(xx, w, h), syy = gaussian(yy, w, h),
                              sxy = gaussian(xy, w, h);
    constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;  // (K L)^2 with L = 1
    double sum = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i];
        const double cov = sxy[i] - mx[i] * my[i];
        sum += (2.0 * mx[i] * my[i] + kC1) * (2.0 * cov + kC2) /
               ((mx[i] * mx[i] + my[i] * my[i] + kC1) * (vx + vy + kC2));
    }
    return sum / double(x.size());
}

}  // namespace

double ssim(const FloatImage& a, const FloatImage& reference) {
    PF_CHECK_EQ(a.rgb.size(), reference.rgb.size());
    if (a.rgb.empty()) return 1.0;
    return ssim_of_luma(display_luma(tonemap_to_srgb8(a)),
                        display_luma(tonemap_to_srgb8(reference)), a.width, a.height);
}

double ssim8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& reference, int width,
             int height) {
    PF_CHECK(a.size() == reference.size() && a.size() == std::size_t(width) * height * 3);
    if (a.empty()) return 1.0;
    return ssim_of_luma(display_luma(a), display_luma(reference), width, height);
}

double psnr8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& reference) {
    PF_CHECK(a.size() == reference.size() && !a.empty());
    double sum = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        const double d = double(a[k]) - double(reference[k]);
        sum += d * d;
    }
    if (sum == 0.0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(255.0 * 255.0 / (sum / double(a.size())));
}

}  // namespace pathfarm
