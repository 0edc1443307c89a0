// A contact sheet: thumbnails of up to 16 evenly spaced frames in a 4-column grid.
#pragma once

#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/film/film.h"

namespace pathfarm::client {

class ContactSheet {
public:
    // every: keep frames 0, every, 2*every, ... (at most 16).
    explicit ContactSheet(int every) : every_(std::max(every, 1)) {}
    void add(uint64_t frame, const FloatImage& image);
    Status write(const std::string& path) const;

private:
    int every_;
    std::vector<std::vector<uint8_t>> thumbs_;  // 8-bit sRGB RGB
    int thumb_w_ = 0, thumb_h_ = 0;
};

}  // namespace pathfarm::client
