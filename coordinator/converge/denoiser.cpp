// Demodulate, accumulate, estimate the variance, filter, remodulate: every per-pixel pass runs
// over rows in parallel (the denoiser shares two cores with the tracers).
#include "coordinator/converge/denoiser.h"

#include <algorithm>
#include <cmath>

#include "coordinator/converge/dilate.h"
#include "coordinator/converge/parallel_rows.h"

namespace pathfarm::coord {
namespace {

// One row of a 3x3 Gaussian's horizontal pass (edges replicated). The loop over the row's
// interior has no clamps, so it vectorises.
void blur3_row(const float* in, float* t, int w) {
    for (int x = 1; x + 1 < w; ++x)
        t[x] = 0.25f * (in[x - 1] + in[x + 1]) + 0.5f * in[x];
    t[0] = 0.75f * in[0] + 0.25f * in[std::min(1, w - 1)];
    t[w - 1] = 0.75f * in[w - 1] + 0.25f * in[std::max(0, w - 2)];
}

// Row y of a 3x3 Gaussian's vertical pass over `tmp` (edges replicated).
void blur3_column(const std::vector<float>& tmp, float* o, int w, int h, int y) {
    const float* up = &tmp[std::size_t(std::max(0, y - 1)) * w];
    const float* mid = &tmp[std::size_t(y) * w];
    const float* down = &tmp[std::size_t(std::min(h - 1, y + 1)) * w];
    for (int x = 0; x < w; ++x)
        o[x] = 0.25f * (up[x] + down[x]) + 0.5f * mid[x];
}

// The mean base colour over each pixel's footprint, which its jittered samples saw, from the
// centre hits: the box average of their linear interpolant, weights 1/8, 3/4, 1/8 per axis
// (edges replicated). Dividing a pixel's light by its centre's base colour alone blew it up
// where a texture edge crosses the pixel (samples on a white texel divided by a saturated blue
// centre: red light 16 times too bright), and the filter spread that. Held at least `floor`.
void footprint_mean(std::vector<Rgb>& a, std::vector<Rgb>& tmp, int w, int h, float floor) {
    tmp.resize(a.size());
    // Over a row's 3w floats: the neighbours of channel c of pixel x are 3 floats away. The
    // interior loops have no clamps, so they vectorise.
    parallel_rows(h, [&](int y) {
        const float* in = &a[std::size_t(y) * w].x;
        float* t = &tmp[std::size_t(y) * w].x;
        const int n = 3 * w;
        for (int j = 3; j + 3 < n; ++j)
            t[j] = 0.125f * (in[j - 3] + in[j + 3]) + 0.75f * in[j];
        for (int c = 0; c < 3; ++c) {
            const int next = std::min(c + 3, n - 3 + c), before = std::max(c, n - 6 + c);
            t[c] = 0.125f * (in[c] + in[next]) + 0.75f * in[c];
            t[n - 3 + c] = 0.125f * (in[before] + in[n - 3 + c]) + 0.75f * in[n - 3 + c];
        }
    });
    parallel_rows(h, [&](int y) {
        const float* up = &tmp[std::size_t(std::max(0, y - 1)) * w].x;
        const float* mid = &tmp[std::size_t(y) * w].x;
        const float* down = &tmp[std::size_t(std::min(h - 1, y + 1)) * w].x;
        float* o = &a[std::size_t(y) * w].x;
        for (int j = 0; j < 3 * w; ++j)
            o[j] = std::max(0.125f * (up[j] + down[j]) + 0.75f * mid[j], floor);
    });
}

}  // namespace

// The frame's G-buffer into the filter's guide: which pixels it filters, and their base colour.
// Not filtered: the sky, sharp pixels, and pixels next to a sharp one (their other samples may
// have seen the emitter or the mirror too: an emitter's edge can be a hundred times brighter
// than the surface, so their light is no smooth irradiance to spread either). The sharp mask
// is dilated by a row pass and a column pass.
void Denoiser::prepare(const GBuffer& g, const Camera& camera) {
    const int w = g.width, h = g.height;
    const std::size_t n = g.distance.size();
    filter_mask_.resize(n);
    near_sharp_.resize(n);
    albedo_.resize(n);
    // Loops over bytes and floats without clamps inside a row, so that they vectorise.
    parallel_rows(h, [&](int y) {
        dilate_row(&g.sharp[std::size_t(y) * w], &near_sharp_[std::size_t(y) * w], w);
    });
    parallel_rows(h, [&](int y) {
        const std::size_t row = std::size_t(y) * w;
        const uint8_t* up = &near_sharp_[std::size_t(std::max(0, y - 1)) * w];
        const uint8_t* mid = &near_sharp_[row];
        const uint8_t* down = &near_sharp_[std::size_t(std::min(h - 1, y + 1)) * w];
        const uint32_t* instance = &g.instance[row];
        uint8_t* mask = &filter_mask_[row];
        for (int x = 0; x < w; ++x)
            mask[x] = uint8_t(instance[x] != GBuffer::kNoInstance) &
                      uint8_t((up[x] | mid[x] | down[x]) == 0);
        std::copy(g.albedo.begin() + row, g.albedo.begin() + row + w, albedo_.begin() + row);
        for (int x = 0; x < w; ++x)
            if (instance[x] == GBuffer::kNoInstance) albedo_[row + x] = Rgb(1.0f);
    });
    footprint_mean(albedo_, albedo_tmp_, w, h, o_.albedo_floor);
    atrous_.set_guide(g, camera, filter_mask_);
}

// Per pixel: the variance of its accumulated light's luminance. Where `variance_frames` or more
// frames are averaged: the variance of one frame's luminance (from the moments) over the frames
// averaged, since the accumulator keeps a running mean, not SVGF's exponential one (SVGF's
// undivided variance over-blurs a still view: on builtin:cornell after 16 frames its relative
// MSE was 0.0152 against 0.0073 divided). With fewer frames: one frame's variance from the
// moments blurred over a 5x5 neighbourhood, undivided (SVGF's spatial estimate, without its edge
// weights: the variance only sets the luminance edge and the geometric edges still stop the
// filter; SVGF's 4/frames boost measured worse here: 0.0179 against 0.0123 relative MSE after
// denoising 4 spp of builtin:cornell).
void Denoiser::estimate_variance(const std::vector<Vec2>& moments, const std::vector<float>* frames,
                                 int w, int h) {
    const std::size_t n = moments.size();
    variance_.resize(n);
    const bool any_short = !frames || std::any_of(frames->begin(), frames->end(), [&](float k) {
        return k < float(o_.variance_frames);
    });
    if (any_short) {  // a still view with history everywhere needs no spatial estimate
        // The moments' two 3x3 Gaussians (a 5x5 binomial), both moments in each pass: the
        // first row pass reads them from the accumulator's pairs.
        for (std::vector<float>* p : {&m1_, &m2_, &tmp_, &tmp2_, &blur1_, &blur2_})
            p->resize(n);
        // One 3x3 Gaussian of planes a and b into out_a and out_b, through tmp_ and tmp2_.
        const auto blur_both = [&](bool from_moments, std::vector<float>& a, std::vector<float>& b,
                                   std::vector<float>& out_a, std::vector<float>& out_b) {
            parallel_rows(h, [&](int y) {
                const std::size_t row = std::size_t(y) * w;
                if (from_moments)
                    for (std::size_t i = row; i < row + w; ++i) {
                        a[i] = moments[i].x;
                        b[i] = moments[i].y;
                    }
                blur3_row(&a[row], &tmp_[row], w);
                blur3_row(&b[row], &tmp2_[row], w);
            });
            parallel_rows(h, [&](int y) {
                const std::size_t row = std::size_t(y) * w;
                blur3_column(tmp_, &out_a[row], w, h, y);
                blur3_column(tmp2_, &out_b[row], w, h, y);
            });
        };
        blur_both(true, m1_, m2_, blur1_, blur2_);
        blur_both(false, blur1_, blur2_, m1_, m2_);
    }
    parallel_rows(h, [&](int y) {
        for (std::size_t i = std::size_t(y) * w; i < std::size_t(y + 1) * w; ++i) {
            const float k = frames ? (*frames)[i] : 1.0f;
            const float own = moments[i].y - moments[i].x * moments[i].x;
            variance_[i] = k >= float(o_.variance_frames)
                               ? std::max(0.0f, own) / k
                               : std::max(0.0f, m2_[i] - m1_[i] * m1_[i]);
        }
    });
}

ConvergeStats Denoiser::filter(FloatImage& image, FrameView view, bool temporal) {
    const GBuffer& g = view.gbuffer;
    const int w = image.width, h = image.height;
    output_is_taa_ = false;
    if (g.width != w || g.height != h) {
        output_ = image;  // no G-buffer for this frame: nothing to stop the filter at edges
        return {};
    }
    ConvergeStats stats{1.0, 0.0, 1.0};
    prepare(g, view.camera);
    parallel_rows(h, [&](int y) {
        for (std::size_t i = std::size_t(y) * w; i < std::size_t(y + 1) * w; ++i)
            for (int c = 0; c < 3; ++c)
                image.rgb[3 * i + c] /= albedo_[i][c];
    });
    if (temporal && o_.edges.model_frames > 0.0f)  // before the accumulator takes the view
        edges_.set_surfaces(g.instance, g.distance, filter_mask_, w, h);
    if (temporal) {
        // The accumulator keeps the view, G-buffer and all, for the next frame's reprojection.
        stats = accumulator_.blend(image, std::move(view));
        estimate_variance(accumulator_.moments(), &accumulator_.history_frames(), w, h);
    } else {
        moments_.resize(std::size_t(w) * std::size_t(h));
        parallel_rows(h, [&](int y) {
            for (std::size_t i = std::size_t(y) * w; i < std::size_t(y + 1) * w; ++i) {
                const float l =
                    luminance(Rgb(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]));
                moments_[i] = Vec2(l, l * l);
            }
        });
        estimate_variance(moments_, nullptr, w, h);
    }
    atrous_.filter(image, variance_, !temporal, albedo_);  // and remodulated
    if (temporal && o_.edges.model_frames > 0.0f)  // the view's G-buffer is the accumulator's now
        edges_.apply(image, accumulator_.history_frames(), accumulator_.gbuffer()->instance,
                     accumulator_.gbuffer()->distance);
    if (temporal && o_.taa_alpha > 0.0f) {
        taa_.apply(image, accumulator_.sources());  // keeps a copy of the output: ours
        output_is_taa_ = true;
    } else {
        output_ = image;
    }
    return stats;
}

void denoise_frame(FloatImage& image, GBuffer gbuffer, const Camera& camera,
                   const DenoiseOptions& options) {
    Denoiser denoiser(options);
    FrameView view;
    view.camera = camera;
    view.gbuffer = std::move(gbuffer);
    denoiser.filter(image, std::move(view), false);
}

}  // namespace pathfarm::coord
