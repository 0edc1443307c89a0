// Analytic daylight: the Preetham et al. (1999) sky and a sun disc, in linear RGB radiance.
// Radiance is scaled so a white Lambert surface facing the sun at noon is about 1.6 (the sun
// irradiance is kSunIrradiance * Environment::sun_scale); the sky below the horizon is black.
#pragma once

#include "common/math/types.h"
#include "common/scene/environment.h"

namespace pathfarm {

inline constexpr float kSunIrradiance = 5.0f;
inline constexpr float kSunHalfAngleRadians = 0.00873f;  // 0.5 degrees

// Everything the sun/sky model evaluates at run time, for backends that evaluate it elsewhere
// (the OpenCL kernels read these numbers).
struct SunSkyParams {
    Vec3 sun_dir;
    float sun_cos_max;
    Rgb sun_radiance;
    float sky_scale;
    float p_sun;
    float perez_y[5], perez_x[5], perez_yy[5];
    float zenith_y, zenith_x, zenith_yy;
    float theta_sun;
    float perez_zenith_y, perez_zenith_x, perez_zenith_yy;  // each Perez function at the zenith
};

struct EnvSample {
    Vec3 wi{0.0f};
    Rgb radiance{0.0f};
    float pdf = 0.0f;  // solid angle
};

class SunSky {
public:
    explicit SunSky(const Environment& env);

    // Radiance arriving from direction w (pointing away from the receiver), sun included.
    Rgb radiance(const Vec3& w) const;
    // Samples the sun cone or the upper hemisphere; pdf() is the matching mixture density.
    EnvSample sample(float u_choice, Vec2 u) const;
    // sample() without the radiance (left zero): a shadow ray may make it unneeded.
    EnvSample sample_direction(float u_choice, Vec2 u) const;
    float pdf(const Vec3& w) const;

    const Vec3& sun_direction() const { return sun_dir_; }
    SunSkyParams params() const;

private:
    Rgb sky_radiance(const Vec3& w) const;
    bool in_sun(const Vec3& w) const { return glm::dot(w, sun_dir_) >= sun_cos_max_; }

    Vec3 sun_dir_;
    float sun_cos_max_;
    Rgb sun_radiance_;
    float sky_scale_;
    float p_sun_;  // probability of sampling the sun rather than the sky
    float perez_y_[5], perez_x_[5], perez_yy_[5];
    float zenith_y_, zenith_x_, zenith_yy_;  // Y (luminance), x, y chromaticity at the zenith
    float theta_sun_;
    // The Perez functions' values at the zenith, which every sky_radiance() divides by.
    float perez_zenith_y_, perez_zenith_x_, perez_zenith_yy_;
};

}  // namespace pathfarm
