// The denoiser on synthetic G-buffers, searched over random configurations: it never carries
// light across a depth step or a crease between two planes (while it does smooth each plane's
// noise), keeps sharp pixels and the sky as they are, is deterministic, and makes nothing
// non-finite out of finite input however extreme.
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "common/math/transform.h"
#include "coordinator/converge/denoiser.h"

namespace pathfarm::coord::denoiser_edges_test {
namespace {

constexpr int kW = 64, kH = 48;

Camera camera_at_origin() {
    Camera c;
    c.camera_to_world = Mat4(1.0f);  // looks down -Z
    c.yfov_radians = glm::radians(45.0f);
    return c;
}

struct Plane {
    Vec3 normal;   // unit, facing the camera
    float offset;  // dot(normal, p) = offset
};

// Where the centre ray of (x, y) meets `plane`; false if it does not (in front of the camera).
bool intersect(const Camera& c, int x, int y, const Plane& plane, float& t) {
    const Ray ray = generate_camera_ray(c, kW, kH, x + 0.5f, y + 0.5f);
    const float denom = glm::dot(plane.normal, ray.d);
    if (std::abs(denom) < 1e-6f) return false;
    t = (plane.offset - glm::dot(plane.normal, ray.o)) / denom;
    return t > 0.0f;
}

// Pixels left of `split` see plane A, the others plane B. Each plane's light is its value times
// (1 + noise), noise uniform in [-amplitude, amplitude].
struct TwoPlanes {
    GBuffer g;
    FloatImage image;
    std::vector<uint8_t> on_a;
};

TwoPlanes two_planes(const Plane& a, const Plane& b, int split, float value_a, float value_b,
                     float amplitude, std::mt19937& rng) {
    const Camera c = camera_at_origin();
    TwoPlanes s;
    s.g.resize(kW, kH);
    s.image = FloatImage(kW, kH);
    s.on_a.assign(std::size_t(kW) * kH, 0);
    std::uniform_real_distribution<float> noise(-amplitude, amplitude);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const bool left = x < split;
            const Plane& p = left ? a : b;
            float t = 0.0f;
            if (!intersect(c, x, y, p, t)) ADD_FAILURE() << "the plane must face the camera";
            const Ray ray = generate_camera_ray(c, kW, kH, x + 0.5f, y + 0.5f);
            const std::size_t i = std::size_t(y) * kW + x;
            s.g.distance[i] = t;
            s.g.instance[i] = left ? 1 : 2;
            s.g.position[i] = ray.o + t * ray.d;
            s.g.normal[i] = p.normal;
            s.g.albedo[i] = Rgb(0.5f);
            s.on_a[i] = left;
            const float v = (left ? value_a : value_b) * (1.0f + noise(rng));
            s.image.set_pixel(x, y, Rgb(v));
        }
    return s;
}

// Mean and standard deviation of plane A's pixels away from the split (where no tap can reach
// across with a correct filter the values stay A's).
struct PlaneStats {
    double mean = 0.0, sd = 0.0, worst = 0.0;  // worst: largest |value / value_a - 1|
};

PlaneStats stats_on_a(const TwoPlanes& s, const FloatImage& img, float value_a) {
    double sum = 0.0, sum2 = 0.0, worst = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < s.on_a.size(); ++i) {
        if (!s.on_a[i]) continue;
        const double v = img.rgb[3 * i];
        sum += v;
        sum2 += v * v;
        worst = std::max(worst, std::abs(v / value_a - 1.0));
        ++n;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean)), worst};
}

// Denoises the two planes (A's value 1, B's 10): A keeps its mean, takes none of B's light and
// loses at least half its noise.
void expect_kept_apart(const TwoPlanes& s, const Camera& camera) {
    FloatImage out = s.image;
    denoise_frame(out, s.g, camera);
    const PlaneStats before = stats_on_a(s, s.image, 1.0f), after = stats_on_a(s, out, 1.0f);
    EXPECT_LT(after.worst, 0.5) << "B's light (10x) leaked into A";
    EXPECT_NEAR(after.mean, 1.0, 0.05);
    EXPECT_LT(after.sd, 0.5 * before.sd) << "the filter must smooth each plane";
}

Vec3 random_facing_normal(std::mt19937& rng, float max_tilt_degrees) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float tilt = glm::radians(max_tilt_degrees) * u(rng);
    const float phi = 2.0f * glm::pi<float>() * u(rng);
    return Vec3(std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt));
}

// Plane B ten times brighter than plane A behind a depth step of at least 10 % of the distance
// (parallel planes, random orientation, depth and split): A's pixels never take B's light, and
// their noise is smoothed.
TEST(DenoiserEdges, NeverCrossADepthStep) {
    std::mt19937 rng(20261202);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int trial = 0; trial < 40; ++trial) {
        const Vec3 n = random_facing_normal(rng, 50.0f);
        const float depth = 2.0f + 20.0f * u(rng);
        const float step = depth * (0.1f + 0.9f * u(rng));
        const bool a_in_front = u(rng) < 0.5f;
        const Plane a{n, -(a_in_front ? depth : depth + step)};
        const Plane b{n, -(a_in_front ? depth + step : depth)};
        const int split = 12 + int(u(rng) * 40.0f);
        const TwoPlanes s = two_planes(a, b, split, 1.0f, 10.0f, 0.5f, rng);
        SCOPED_TRACE(::testing::Message() << "trial " << trial << " depth " << depth << " step "
                                          << step << " split " << split);
        expect_kept_apart(s, camera_at_origin());
    }
}

// Two planes meeting in a crease (the same points along the seam, normals 30 to 90 degrees
// apart): the normal edge keeps them apart.
TEST(DenoiserEdges, NeverCrossACrease) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Camera c = camera_at_origin();
    for (int trial = 0; trial < 40; ++trial) {
        const int split = 12 + int(u(rng) * 40.0f);
        // The seam: the vertical line through the split column's left edge at this depth.
        const float depth = 3.0f + 10.0f * u(rng);
        const Ray edge = generate_camera_ray(c, kW, kH, float(split), 0.5f * kH);
        const Vec3 seam_point = edge.d * (depth / -edge.d.z);
        const float angle = glm::radians(30.0f + 60.0f * u(rng));
        // Both normals face the camera: a convex or concave crease about the vertical seam.
        const float base = glm::radians(-40.0f + 80.0f * u(rng));
        const float left_yaw = base - 0.5f * angle, right_yaw = base + 0.5f * angle;
        const bool convex = u(rng) < 0.5f;
        auto normal = [&](float yaw) { return Vec3(std::sin(yaw), 0.0f, std::cos(yaw)); };
        const Vec3 na = normal(convex ? left_yaw : right_yaw);
        const Vec3 nb = normal(convex ? right_yaw : left_yaw);
        const Plane a{na, glm::dot(na, seam_point)}, b{nb, glm::dot(nb, seam_point)};
        float t = 0.0f;
        if (!intersect(c, 0, 0, a, t) || !intersect(c, kW - 1, 0, b, t)) continue;  // edge-on
        const TwoPlanes s = two_planes(a, b, split, 1.0f, 10.0f, 0.5f, rng);
        SCOPED_TRACE(::testing::Message() << "trial " << trial << " angle " << glm::degrees(angle)
                                          << " split " << split);
        expect_kept_apart(s, c);
    }
}

// Random G-buffers and images: misses, sharp pixels, black and extreme values (0 to 1e30),
// zero albedo, grazing normals. Output finite everywhere; sharp pixels and the sky unchanged;
// the same bytes twice.
TEST(DenoiserEdges, FiniteDeterministicAndSharpPixelsKept) {
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Camera c = camera_at_origin();
    for (int trial = 0; trial < 20; ++trial) {
        GBuffer g;
        g.resize(kW, kH);
        FloatImage image(kW, kH);
        for (std::size_t i = 0; i < g.distance.size(); ++i) {
            const float kind = u(rng);
            const float scale = std::pow(10.0f, -3.0f + 33.0f * u(rng) * u(rng) * u(rng));
            for (int ch = 0; ch < 3; ++ch)
                image.rgb[3 * i + ch] = u(rng) < 0.2f ? 0.0f : scale * u(rng);
            if (kind < 0.1f) continue;  // the sky
            const Ray ray =
                generate_camera_ray(c, kW, kH, float(i % kW) + 0.5f, float(i / kW) + 0.5f);
            g.distance[i] = 0.01f + 1000.0f * u(rng) * u(rng);
            g.instance[i] = 1 + uint32_t(u(rng) * 3.0f);
            g.position[i] = ray.o + g.distance[i] * ray.d;
            g.normal[i] = glm::normalize(Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) * 0.01f));
            g.albedo[i] = u(rng) < 0.2f ? Rgb(0.0f) : Rgb(u(rng), u(rng), u(rng));
            g.sharp[i] = kind < 0.2f;
        }
        FloatImage once = image, twice = image;
        denoise_frame(once, g, c);
        denoise_frame(twice, g, c);
        ASSERT_EQ(std::memcmp(once.rgb.data(), twice.rgb.data(), once.rgb.size() * 4), 0)
            << "trial " << trial;
        for (std::size_t i = 0; i < g.distance.size(); ++i) {
            for (int ch = 0; ch < 3; ++ch) {
                const float v = once.rgb[3 * i + ch], in = image.rgb[3 * i + ch];
                ASSERT_TRUE(std::isfinite(v)) << "trial " << trial << " pixel " << i;
                if (!g.hit(i) || g.sharp[i]) {
                    ASSERT_NEAR(v, in, 1e-6f * in) << "trial " << trial << " pixel " << i;
                }
            }
        }
    }
}

}  // namespace
}  // namespace pathfarm::coord::denoiser_edges_test
