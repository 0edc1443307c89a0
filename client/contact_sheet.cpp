// Box-filtered thumbnails, tonemapped like the frames.
#include "client/contact_sheet.h"

#include "common/film/image_io.h"
#include "common/film/tonemap.h"

namespace pathfarm::client {

void ContactSheet::add(uint64_t frame, const FloatImage& image) {
    if (frame % uint64_t(every_) != 0 || thumbs_.size() >= 16 || image.width <= 0) return;
    const int scale = std::max(1, image.width / 160);
    FloatImage small(image.width / scale, image.height / scale);
    for (int y = 0; y < small.height * scale; ++y)
        for (int x = 0; x < small.width * scale; ++x)
            small.set_pixel(
                x / scale, y / scale,
                small.pixel(x / scale, y / scale) + image.pixel(x, y) / float(scale * scale));
    thumb_w_ = small.width;
    thumb_h_ = small.height;
    thumbs_.push_back(tonemap_to_srgb8(small));
}

Status ContactSheet::write(const std::string& path) const {
    if (thumbs_.empty())
        return make_error(ErrorCode::invalid_argument, "{}: no frames for a contact sheet", path);
    const int cols = 4, rows = int((thumbs_.size() + 3) / 4);
    std::vector<uint8_t> sheet(std::size_t(cols * thumb_w_) * rows * thumb_h_ * 3, 32);
    for (std::size_t t = 0; t < thumbs_.size(); ++t) {
        const int ox = int(t % 4) * thumb_w_, oy = int(t / 4) * thumb_h_;
        for (int y = 0; y < thumb_h_; ++y)
            std::copy_n(&thumbs_[t][std::size_t(y) * thumb_w_ * 3], thumb_w_ * 3,
                        &sheet[(std::size_t(oy + y) * cols * thumb_w_ + ox) * 3]);
    }
    return write_rgb8(path, cols * thumb_w_, rows * thumb_h_, sheet);
}

}  // namespace pathfarm::client
