// STEP, LINEAR (lerp / slerp) and CUBICSPLINE (Hermite) keyframe interpolation.
#include "coordinator/animation/keyframe_track.h"

#include <algorithm>
#include <cmath>

namespace pathfarm::coord {
namespace {

// Values of key k: for cubic splines the middle of (in-tangent, value, out-tangent).
const float* key_value(const AnimationSampler& s, std::size_t k, int count) {
    const std::size_t stride = s.interpolation == Interpolation::cubic_spline ? 3 : 1;
    return s.values.data() + (k * stride + (stride == 3 ? 1 : 0)) * count;
}

void normalize_quat(float* q) {
    const double len = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] +
                                 double(q[3]) * q[3]);
    if (len > 0.0)
        for (int i = 0; i < 4; ++i)
            q[i] = float(q[i] / len);
}

void hermite(const AnimationSampler& s, std::size_t k, double u, double dt, int count, float* out) {
    const float* v0 = s.values.data() + (3 * k + 1) * count;
    const float* b0 = s.values.data() + (3 * k + 2) * count;  // out-tangent of key k
    const float* v1 = s.values.data() + (3 * (k + 1) + 1) * count;
    const float* a1 = s.values.data() + (3 * (k + 1)) * count;  // in-tangent of key k+1
    const double u2 = u * u, u3 = u2 * u;
    const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
                 h11 = u3 - u2;
    for (int c = 0; c < count; ++c)  // tangents are scaled by the key interval (glTF Appendix C)
        out[c] = float(h00 * v0[c] + h10 * dt * b0[c] + h01 * v1[c] + h11 * dt * a1[c]);
}

}  // namespace

void slerp(const float* q0, const float* q1, double u, float* out) {
    double a[4], b[4];
    double dot = 0.0;
    for (int i = 0; i < 4; ++i) {
        a[i] = q0[i];
        b[i] = q1[i];
        dot += a[i] * b[i];
    }
    if (dot < 0.0) {  // shortest path
        for (double& x : b)
            x = -x;
        dot = -dot;
    }
    double s0 = 1.0 - u, s1 = u;
    if (dot < 0.9999995) {
        const double theta = std::acos(std::min(dot, 1.0));
        const double sin_theta = std::sin(theta);
        s0 = std::sin((1.0 - u) * theta) / sin_theta;
        s1 = std::sin(u * theta) / sin_theta;
    }
    for (int i = 0; i < 4; ++i)
        out[i] = float(s0 * a[i] + s1 * b[i]);
    normalize_quat(out);
}

void sample_keyframes(const AnimationSampler& s, float t, int count, bool rotation, float* out) {
    const std::size_t keys = s.times.size();
    const auto copy = [&](const float* v) { std::copy(v, v + count, out); };
    if (keys == 1 || t <= s.times.front()) {
        copy(key_value(s, 0, count));
    } else if (t >= s.times.back()) {
        copy(key_value(s, keys - 1, count));
    } else {
        const std::size_t k =
            std::size_t(std::upper_bound(s.times.begin(), s.times.end(), t) - s.times.begin()) - 1;
        const double dt = double(s.times[k + 1]) - double(s.times[k]);
        const double u = (double(t) - double(s.times[k])) / dt;
        switch (s.interpolation) {
            case Interpolation::step:
                copy(key_value(s, k, count));
                break;
            case Interpolation::cubic_spline:
                hermite(s, k, u, dt, count, out);
                break;
            case Interpolation::linear:
            default:
                if (rotation) {
                    slerp(key_value(s, k, count), key_value(s, k + 1, count), u, out);
                } else {
                    const float* v0 = key_value(s, k, count);
                    const float* v1 = key_value(s, k + 1, count);
                    for (int c = 0; c < count; ++c)
                        out[c] = float(v0[c] + (double(v1[c]) - v0[c]) * u);
                }
        }
    }
    if (rotation) normalize_quat(out);
}

}  // namespace pathfarm::coord
