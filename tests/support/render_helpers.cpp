// Test render helpers.
#include "tests/support/render_helpers.h"

#include <cstdlib>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_builder.h"
#include "tracer-node/backend/render_backend.h"

namespace pathfarm::test {
namespace {

Camera inside_camera() {
    Camera cam;
    cam.yfov_radians = glm::radians(50.0f);
    cam.camera_to_world = glm::inverse(glm::lookAt(Vec3(0, 0, 2.5f), Vec3(0), Vec3(0, 1, 0)));
    return cam;
}

// Regularised incomplete beta by Lentz's continued fraction.
double incomplete_beta(double a, double b, double x) {
    if (x <= 0.0) return 0.0;
    if (x >= 1.0) return 1.0;
    const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                  a * std::log(x) + b * std::log1p(-x));
    if (x > (a + 1.0) / (a + b + 2.0)) return 1.0 - incomplete_beta(b, a, 1.0 - x);
    double f = 1.0, c = 1.0, d = 0.0;
    for (int i = 0; i <= 400; ++i) {
        const int m = i / 2;
        double num;
        if (i == 0)
            num = 1.0;
        else if (i % 2 == 0)
            num = m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
        else
            num = -((a + m) * (a + b + m) * x) / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
        d = 1.0 + num * d;
        d = std::abs(d) < 1e-300 ? 1e-300 : d;
        d = 1.0 / d;
        c = 1.0 + num / c;
        c = std::abs(c) < 1e-300 ? 1e-300 : c;
        const double cd = c * d;
        f *= cd;
        if (std::abs(1.0 - cd) < 1e-12) break;
    }
    return front * (f - 1.0) / a;
}

struct Moments {
    double mean, var_of_mean;
    int n;
};

Moments moments(const std::vector<double>& v) {
    double m = 0.0;
    for (double x : v)
        m += x;
    m /= double(v.size());
    double s = 0.0;
    for (double x : v)
        s += (x - m) * (x - m);
    return {m, s / double(v.size() - 1) / double(v.size()), int(v.size())};
}

// One-sample t-test of a against the constant c (b's every batch was the same value).
double one_sample_p(const Moments& a, double c) {
    if (a.var_of_mean <= 0.0) return a.mean == c ? 1.0 : 0.0;
    return student_t_p_value((a.mean - c) / std::sqrt(a.var_of_mean), a.n - 1);
}

// Welch's test of equal means. A side whose batches are all equal (typically all 0) has no
// variance estimate: the other side is tested against that constant, which is how an estimator
// that is black where the other is lit fails. b_sparse marks b as an estimator that may miss a
// small contribution in every batch (BSDF sampling of a small light): a constant b is then no
// evidence and the block is left to the image-mean test.
double welch_p(const Moments& a, const Moments& b, bool b_sparse) {
    const double se2 = a.var_of_mean + b.var_of_mean;
    if (se2 <= 0.0) return a.mean == b.mean ? 1.0 : 0.0;
    if (b.var_of_mean <= 0.0) return b_sparse ? 1.0 : one_sample_p(a, b.mean);
    if (a.var_of_mean <= 0.0) return one_sample_p(b, a.mean);
    const double t = (a.mean - b.mean) / std::sqrt(se2);
    const double dof =
        se2 * se2 /
        (a.var_of_mean * a.var_of_mean / (a.n - 1) + b.var_of_mean * b.var_of_mean / (b.n - 1));
    return student_t_p_value(t, dof);
}

}  // namespace

double student_t_p_value(double t, double dof) {
    return incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t));
}

tracer::BackendKind default_backend() {
    const char* name = std::getenv("PATHFARM_TEST_BACKEND");
    if (name == nullptr || *name == '\0') return tracer::BackendKind::embree;
    auto kind = tracer::parse_backend_kind(name);
    EXPECT_TRUE(kind.ok()) << "PATHFARM_TEST_BACKEND=" << name;
    return kind.ok() ? *kind : tracer::BackendKind::embree;
}

std::vector<FloatImage> render_seeds(const SceneModel& scene, const RenderRequest& r, int count) {
    auto backend = tracer::create_backend(r.backend, {r.threads, 0, 0, r.texture_lod});
    EXPECT_TRUE(backend.ok()) << (backend.ok() ? "" : backend.error().message);
    if (!backend.ok()) return std::vector<FloatImage>(std::size_t(count));
    SceneModel local = scene;  // rendered relative to the camera, as the tools do
    Camera camera = recentre_on_camera(
        local, scene.cameras.empty()
                   ? frame_bounds(world_bounds(scene), float(r.width) / float(r.height))
                   : scene.cameras[0]);
    EXPECT_TRUE((*backend)->set_scene(local).ok());
    std::vector<int> bounds{0};
    bounds.insert(bounds.end(), r.row_splits.begin(), r.row_splits.end());
    bounds.push_back(r.height);
    std::vector<FloatImage> images;
    for (int i = 0; i < count; ++i) {
        FloatImage& image = images.emplace_back(r.width, r.height);
        for (std::size_t k = 0; k + 1 < bounds.size(); ++k) {
            tracer::RenderJob job;
            job.frame =
                FrameSpec{r.width, r.height, r.frame, r.seed + uint32_t(i), r.spp, 0, camera};
            job.integrator = r.integrator;
            job.y0 = bounds[k];
            job.y1 = bounds[k + 1];
            auto stats = (*backend)->render_rows(job, image.row(job.y0));
            EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
        }
    }
    return images;
}

FloatImage render(const SceneModel& scene, const RenderRequest& r) {
    return std::move(render_seeds(scene, r, 1).front());
}

SceneModel make_furnace(float emission, float albedo) {
    SceneBuilder b("furnace");
    Material m = make_lambert("glow", Rgb(albedo));
    m.emissive_factor = Rgb(emission);
    const int mat = b.add_material(m);
    b.add_instance(b.add_mesh(turned_inside_out(make_sphere(4.0f, 24, 48, mat))), Mat4(1.0f));
    b.add_instance(b.add_mesh(make_sphere(1.0f, 24, 48, mat)), Mat4(1.0f));
    b.add_camera(inside_camera());
    b.environment().sky = SkyMode::off;
    return b.finish();
}

SceneModel make_lit_sphere(float emission, float rho) {
    SceneBuilder b("lit-sphere");
    const int glow = b.add_material(make_emitter("enclosure", Rgb(emission)));
    const int diffuse = b.add_material(make_lambert("ball", Rgb(rho)));
    b.add_instance(b.add_mesh(turned_inside_out(make_sphere(4.0f, 24, 48, glow))), Mat4(1.0f));
    b.add_instance(b.add_mesh(make_sphere(1.0f, 24, 48, diffuse)), Mat4(1.0f));
    b.add_camera(inside_camera());
    b.environment().sky = SkyMode::off;
    return b.finish();
}

FloatImage downsample(const FloatImage& img, int block) {
    FloatImage out(img.width / block, img.height / block);
    const float weight = 1.0f / float(block * block);
    for (int y = 0; y < out.height * block; ++y)
        for (int x = 0; x < out.width * block; ++x)
            out.set_pixel(x / block, y / block,
                          out.pixel(x / block, y / block) + img.pixel(x, y) * weight);
    return out;
}

AgreementResult compare_batches(const std::vector<FloatImage>& a_in,
                                const std::vector<FloatImage>& b_in, double alpha, int block,
                                bool b_sparse) {
    std::vector<FloatImage> a, b;
    for (const FloatImage& img : a_in)
        a.push_back(block > 1 ? downsample(img, block) : img);
    for (const FloatImage& img : b_in)
        b.push_back(block > 1 ? downsample(img, block) : img);
    AgreementResult r;
    const std::size_t values = a.at(0).rgb.size();
    r.pixel_threshold = 1.0 - std::pow(1.0 - alpha, 1.0 / double(values));
    std::vector<double> xa(a.size()), xb(b.size()), ma(a.size(), 0.0), mb(b.size(), 0.0);
    for (std::size_t i = 0; i < values; ++i) {
        for (std::size_t k = 0; k < a.size(); ++k) {
            xa[k] = a[k].rgb[i];
            ma[k] += a[k].rgb[i] / double(values);
        }
        for (std::size_t k = 0; k < b.size(); ++k) {
            xb[k] = b[k].rgb[i];
            mb[k] += b[k].rgb[i] / double(values);
        }
        const Moments mom_a = moments(xa), mom_b = moments(xb);
        const double p = welch_p(mom_a, mom_b, b_sparse);
        if (p < r.min_pixel_p) {
            r.min_pixel_p = p;
            r.worst_value = i;
            r.worst_a = mom_a.mean;
            r.worst_b = mom_b.mean;
        }
    }
    r.mean_p = welch_p(moments(ma), moments(mb), false);
    return r;
}

}  // namespace pathfarm::test
