// Box-filtered thumbnails of the frames as shown.
#include "client/contact_sheet.h"

#include "common/film/image_io.h"

namespace pathfarm::client {

void ContactSheet::add(uint64_t frame, int width, int height, const std::vector<uint8_t>& srgb8) {
    if (frame % uint64_t(every_) != 0 || thumbs_.size() >= 16 || width <= 0) return;
    const int scale = std::max(1, width / 160);
    const int tw = width / scale, th = height / scale;
    if (!thumbs_.empty() && (tw != thumb_w_ || th != thumb_h_)) return;  // one size per sheet
    std::vector<uint8_t> thumb(std::size_t(tw) * th * 3);
    for (int y = 0; y < th; ++y)
        for (int x = 0; x < tw; ++x)
            for (int c = 0; c < 3; ++c) {
                int sum = 0;
                for (int dy = 0; dy < scale; ++dy)
                    for (int dx = 0; dx < scale; ++dx)
                        sum +=
                            srgb8[(std::size_t(y * scale + dy) * width + x * scale + dx) * 3 + c];
                thumb[(std::size_t(y) * tw + x) * 3 + c] = uint8_t(sum / (scale * scale));
            }
    thumb_w_ = tw;
    thumb_h_ = th;
    thumbs_.push_back(std::move(thumb));
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
