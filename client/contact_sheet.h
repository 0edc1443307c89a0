// A contact sheet: thumbnails of up to 16 evenly spaced frames in a 4-column grid.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "common/base/result.h"

namespace pathfarm::client {

class ContactSheet {
public:
    // every: keep frames 0, every, 2*every, ... (at most 16).
    explicit ContactSheet(int every) : every_(std::max(every, 1)) {}
    // srgb8: width*height*3 display bytes, row 0 at the top.
    void add(uint64_t frame, int width, int height, const std::vector<uint8_t>& srgb8);
    Status write(const std::string& path) const;

private:
    int every_;
    std::vector<std::vector<uint8_t>> thumbs_;  // 8-bit sRGB RGB
    int thumb_w_ = 0, thumb_h_ = 0;
};

}  // namespace pathfarm::client
