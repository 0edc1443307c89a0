// Preetham sky: Perez distribution with turbidity-dependent coefficients, zenith values from
// the paper's fits, CIE xyY converted to linear sRGB.
#include "common/render/sun_sky.h"

#include "common/math/frame.h"
#include "common/sampling/sampling.h"

namespace pathfarm {
namespace {

float perez(const float c[5], float cos_theta, float gamma, float cos_gamma) {
    return (1.0f + c[0] * std::exp(c[1] / std::max(cos_theta, 0.01f))) *
           (1.0f + c[2] * std::exp(c[3] * gamma) + c[4] * cos_gamma * cos_gamma);
}

Rgb xyy_to_rgb(float x, float y, float luminance_y) {
    if (y <= 0.0f) return Rgb(0.0f);
    const float cx = x / y * luminance_y;
    const float cz = (1.0f - x - y) / y * luminance_y;
    return glm::max(Rgb(3.2406f * cx - 1.5372f * luminance_y - 0.4986f * cz,
                        -0.9689f * cx + 1.8758f * luminance_y + 0.0415f * cz,
                        0.0557f * cx - 0.2040f * luminance_y + 1.0570f * cz),
                    Rgb(0.0f));
}

float zenith_chromaticity(float t, float th, const float c[3][4]) {
    const float th2 = th * th, th3 = th2 * th;
    float v = 0.0f;
    const float tp[3] = {t * t, t, 1.0f};
    for (int r = 0; r < 3; ++r)
        v += tp[r] * (c[r][0] * th3 + c[r][1] * th2 + c[r][2] * th + c[r][3]);
    return v;
}

}  // namespace

SunSky::SunSky(const Environment& env) {
    sun_dir_ = glm::normalize(env.sun_direction);
    sun_cos_max_ = std::cos(kSunHalfAngleRadians);
    const float t = std::clamp(env.turbidity, 1.7f, 10.0f);
    theta_sun_ = std::acos(std::clamp(sun_dir_.y, 0.0f, 1.0f));
    const float py[5] = {0.1787f * t - 1.4630f, -0.3554f * t + 0.4275f, -0.0227f * t + 5.3251f,
                         0.1206f * t - 2.5771f, -0.0670f * t + 0.3703f};
    const float px[5] = {-0.0193f * t - 0.2592f, -0.0665f * t + 0.0008f, -0.0004f * t + 0.2125f,
                         -0.0641f * t - 0.8989f, -0.0033f * t + 0.0452f};
    const float pyy[5] = {-0.0167f * t - 0.2608f, -0.0950f * t + 0.0092f, -0.0079f * t + 0.2102f,
                          -0.0441f * t - 1.6537f, -0.0109f * t + 0.0529f};
    std::copy(py, py + 5, perez_y_);
    std::copy(px, px + 5, perez_x_);
    std::copy(pyy, pyy + 5, perez_yy_);
    const float chi = (4.0f / 9.0f - t / 120.0f) * (kPi - 2.0f * theta_sun_);
    zenith_y_ = (4.0453f * t - 4.9710f) * std::tan(chi) - 0.2155f * t + 2.4192f;
    static const float cx[3][4] = {{0.00166f, -0.00375f, 0.00209f, 0.0f},
                                   {-0.02903f, 0.06377f, -0.03202f, 0.00394f},
                                   {0.11693f, -0.21196f, 0.06052f, 0.25886f}};
    static const float cy[3][4] = {{0.00275f, -0.00610f, 0.00317f, 0.0f},
                                   {-0.04214f, 0.08970f, -0.04153f, 0.00516f},
                                   {0.15346f, -0.26756f, 0.06670f, 0.26688f}};
    zenith_x_ = zenith_chromaticity(t, theta_sun_, cx);
    zenith_yy_ = zenith_chromaticity(t, theta_sun_, cy);
    const float cos_ts = std::cos(theta_sun_);
    perez_zenith_y_ = perez(perez_y_, 1.0f, theta_sun_, cos_ts);
    perez_zenith_x_ = perez(perez_x_, 1.0f, theta_sun_, cos_ts);
    perez_zenith_yy_ = perez(perez_yy_, 1.0f, theta_sun_, cos_ts);

    // Units: the paper's zenith luminance is in kcd/m^2 (about 5-10 at midday); 0.04 maps it
    // to display-friendly radiance. The sun's radiance gives kSunIrradiance at normal incidence.
    sky_scale_ = 0.04f * env.sun_scale;
    const float sun_solid_angle = 2.0f * kPi * (1.0f - sun_cos_max_);
    const float above = sun_dir_.y > 0.0f ? 1.0f : 0.0f;
    sun_radiance_ =
        Rgb(1.0f, 0.93f, 0.82f) * (above * kSunIrradiance * env.sun_scale / sun_solid_angle);
    const float sky_power = kPi * luminance(sky_radiance(Vec3(0, 1, 0)));
    const float sun_power = luminance(sun_radiance_) * sun_solid_angle;
    p_sun_ = sun_power + sky_power > 0.0f
                 ? std::clamp(sun_power / (sun_power + sky_power), 0.1f, 0.9f)
                 : 0.0f;
    if (above == 0.0f) p_sun_ = 0.0f;
}

SunSkyParams SunSky::params() const {
    SunSkyParams p{};
    p.sun_dir = sun_dir_;
    p.sun_cos_max = sun_cos_max_;
    p.sun_radiance = sun_radiance_;
    p.sky_scale = sky_scale_;
    p.p_sun = p_sun_;
    std::copy(perez_y_, perez_y_ + 5, p.perez_y);
    std::copy(perez_x_, perez_x_ + 5, p.perez_x);
    std::copy(perez_yy_, perez_yy_ + 5, p.perez_yy);
    p.zenith_y = zenith_y_;
    p.zenith_x = zenith_x_;
    p.zenith_yy = zenith_yy_;
    p.theta_sun = theta_sun_;
    p.perez_zenith_y = perez_zenith_y_;
    p.perez_zenith_x = perez_zenith_x_;
    p.perez_zenith_yy = perez_zenith_yy_;
    return p;
}

Rgb SunSky::sky_radiance(const Vec3& w) const {
    if (w.y <= 0.0f) return Rgb(0.0f);
    const float cos_gamma = std::clamp(glm::dot(w, sun_dir_), -1.0f, 1.0f);
    const float gamma = std::acos(cos_gamma);
    const float y = zenith_y_ * perez(perez_y_, w.y, gamma, cos_gamma) / perez_zenith_y_;
    const float x = zenith_x_ * perez(perez_x_, w.y, gamma, cos_gamma) / perez_zenith_x_;
    const float yy = zenith_yy_ * perez(perez_yy_, w.y, gamma, cos_gamma) / perez_zenith_yy_;
    return xyy_to_rgb(x, yy, std::max(y, 0.0f)) * sky_scale_;
}

Rgb SunSky::radiance(const Vec3& w) const {
    Rgb l = sky_radiance(w);
    if (in_sun(w)) l += sun_radiance_;
    return l;
}

EnvSample SunSky::sample(float u_choice, Vec2 u) const {
    EnvSample s = sample_direction(u_choice, u);
    s.radiance = radiance(s.wi);
    return s;
}

EnvSample SunSky::sample_direction(float u_choice, Vec2 u) const {
    EnvSample s;
    if (u_choice < p_sun_) {
        s.wi = Frame::from_normal(sun_dir_).to_world(sample_uniform_cone(u, sun_cos_max_));
    } else {
        // Uniform over the upper (+Y) hemisphere.
        const Vec3 h = sample_uniform_sphere(Vec2(0.5f * u.x, u.y));
        s.wi = Vec3(h.x, h.z, h.y);
    }
    s.pdf = pdf(s.wi);
    return s;
}

float SunSky::pdf(const Vec3& w) const {
    float p = w.y > 0.0f ? (1.0f - p_sun_) / (2.0f * kPi) : 0.0f;
    if (p_sun_ > 0.0f && in_sun(w)) p += p_sun_ * uniform_cone_pdf(sun_cos_max_);
    return p;
}

}  // namespace pathfarm
