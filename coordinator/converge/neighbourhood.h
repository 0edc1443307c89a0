// The mean and standard deviation of every pixel's 3x3 neighbourhood (the pixels of it inside
// the image), per channel: what the history clamp of a moving view compares the history with.
// Two separable passes, rows then columns, that vectorise, instead of nine taps per pixel
// (under a turning camera every pixel is clamped).
#pragma once

#include <cstddef>
#include <vector>

#include "common/film/film.h"

namespace pathfarm::coord {

class NeighbourhoodStats {
public:
    // The statistics of `image`'s pixels; the planes are kept from frame to frame.
    void compute(const FloatImage& image);
    Rgb mean(std::size_t pixel) const { return at(mean_, pixel); }
    Rgb sigma(std::size_t pixel) const { return at(sigma_, pixel); }

private:
    static Rgb at(const std::vector<float>& plane, std::size_t pixel) {
        return {plane[3 * pixel], plane[3 * pixel + 1], plane[3 * pixel + 2]};
    }
    std::vector<float> sum_, sum2_;  // along each row: the pixel and its left and right neighbours
    std::vector<float> mean_, sigma_;
};

}  // namespace pathfarm::coord
