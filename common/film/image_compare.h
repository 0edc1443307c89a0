// Image error metrics used by tests and benchmarks (always against a converged reference).
#pragma once

#include <cstdint>
#include <vector>

#include "common/film/film.h"

namespace pathfarm {

// Root mean squared error over all pixels and channels. Images must have the same size.
double rmse(const FloatImage& a, const FloatImage& reference);
// Mean over pixels and channels of (a - ref)^2 / (ref^2 + eps): comparable across scenes whose
// radiance differs by orders of magnitude.
double relative_mse(const FloatImage& a, const FloatImage& reference, double eps = 1e-2);

// Structural similarity (Wang et al. 2004) of the two images as a viewer sees them: the luma of
// their tonemapped sRGB values in [0, 1], an 11x11 Gaussian window (sigma 1.5) clipped at the
// borders, the paper's constants. 1 for identical images. Same size required.
double ssim(const FloatImage& a, const FloatImage& reference);
// The same of two sRGB frames of 8-bit values (width*height*3): what a codec's decoder shows
// against what it was given.
double ssim8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& reference, int width,
             int height);

// Peak signal-to-noise ratio in dB of 8-bit values (what a codec is judged by): 10 log10(255^2 /
// MSE) over every byte; infinity for identical inputs. Same size required.
double psnr8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& reference);

}  // namespace pathfarm
