// Emissive-triangle selection (by power, or through the light tree) and sun/sky sampling.
#include "common/render/light_sampler.h"

#include <algorithm>

#include "common/sampling/sampling.h"
#include "common/scene/alpha.h"

namespace pathfarm {
namespace {

// Mean texel value of an image (sRGB-decoded), so textured emitters are chosen by their
// actual average emission.
Rgb mean_emission_texel(const Image* image) {
    if (image == nullptr || image->width <= 0) return Rgb(1.0f);
    Rgb sum(0.0f);
    const std::size_t n = std::size_t(image->width) * image->height;
    const std::size_t step = std::max<std::size_t>(1, n / 4096);
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; i += step, ++count)
        for (int c = 0; c < 3; ++c)
            sum[c] += srgb_to_linear(image->rgba[i * 4 + c] / 255.0f);
    return sum / float(std::max<std::size_t>(count, 1));
}

}  // namespace

std::optional<LightSelection> parse_light_selection(std::string_view name) {
    for (LightSelection s :
         {LightSelection::power, LightSelection::tree, LightSelection::automatic})
        if (name == light_selection_name(s)) return s;
    return std::nullopt;
}

LightSampler::LightSampler(const ShadingScene& shading, const std::vector<bool>& excluded,
                           LightSelection selection, LightTopologyCache* topology)
    : shading_(shading), requested_(selection), selection_(selection) {
    const SceneModel& scene = shading.model();
    instance_offset_.assign(scene.instances.size(), -1);
    std::vector<double> power;
    std::vector<LightBounds> bounds;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Mesh& mesh = scene.meshes[scene.instances[i].mesh];
        const Material& mat = scene.materials[mesh.material];
        if (!mat.is_emissive() || mesh.triangle_count() == 0) continue;
        if (i < excluded.size() && excluded[i]) continue;
        const Rgb mean =
            mat.emission() * mean_emission_texel(scene.texture_image(mat.emissive_texture));
        const float sides = mat.double_sided ? 2.0f : 1.0f;
        instance_offset_[i] = int64_t(triangles_.size());
        for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
            Vec3 p[3];
            shading.triangle_vertices(i, t, p);
            const Vec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
            const float area = 0.5f * glm::length(c);
            SurfacePoint probe = shading.surface(Hit{0.0f, i, t, 1.0f / 3.0f, 1.0f / 3.0f});
            triangles_.push_back(
                {i, t, mesh.material, p[0], p[1] - p[0], p[2] - p[0], probe.ng, area});
            power.push_back(double(luminance(mean)) * area * sides);
            if (selection != LightSelection::power)
                bounds.push_back(triangle_light_bounds(p[0], p[1], p[2], probe.ng,
                                                       float(power.back()), mat.double_sided));
        }
    }
    cdf_ = GuidedCdf::from_weights(power);
    if (selection != LightSelection::power) {
        LightTopologyCache local;
        make_tree(bounds, topology ? *topology : local);
    }
    if (selection == LightSelection::automatic) {
        choice_ = measure_choice();
        selection_ = choice_.selection;
        if (selection_ == LightSelection::power) tree_ = LightTree();
    }
    if (uses_sun_sky(scene)) {
        sun_sky_ = std::make_unique<SunSky>(scene.environment);
        p_environment_ = triangles_.empty() ? 1.0f : 0.5f;
    }
}

void LightSampler::make_tree(const std::vector<LightBounds>& bounds, LightTopologyCache& topology) {
    if (bounds.size() < kClusteredFrom) {
        tree_ = LightTree(bounds);
        return;
    }
    const SceneModel& scene = shading_.model();
    std::vector<LightTree::Cluster> clusters;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        if (instance_offset_[i] < 0) continue;
        const Mesh& mesh = scene.meshes[scene.instances[i].mesh];
        const LightTree& mesh_tree =
            topology.mesh_tree(mesh, scene.materials[mesh.material].double_sided);
        for (const LightTree::Cluster& c : mesh_tree.clusters(uint32_t(instance_offset_[i])))
            clusters.push_back(c);
    }
    tree_ = LightTree(bounds, clusters);
    topology.end_state();
}

float LightSampler::selection_pmf(std::size_t k, const Vec3& from, const Vec3& normal) const {
    if (selection_ == LightSelection::tree) return tree_.pmf(from, normal, uint32_t(k));
    return cdf_.pmf(k);
}

std::optional<LightSample> LightSampler::sample(const Vec3& from, const Vec3& normal,
                                                float u_select, Vec2 u,
                                                bool defer_environment) const {
    if (empty()) return std::nullopt;
    LightSample ls;
    if (u_select < p_environment_) {
        const float u_choice = u_select / p_environment_;
        const EnvSample es = defer_environment ? sun_sky_->sample_direction(u_choice, u)
                                               : sun_sky_->sample(u_choice, u);
        if (es.pdf <= 0.0f) return std::nullopt;
        ls.p = es.wi;
        ls.radiance = es.radiance;
        ls.pdf = p_environment_ * es.pdf;
        ls.environment = true;
        ls.radiance_deferred = defer_environment;
        return ls;
    }
    const float us = (u_select - p_environment_) / (1.0f - p_environment_);
    std::size_t k;
    float pmf;
    if (selection_ == LightSelection::tree) {
        const auto choice = tree_.sample(from, normal, us);
        if (!choice) return std::nullopt;
        k = choice->emitter;
        pmf = choice->pmf;
    } else {
        k = std::min(cdf_.upper_bound(us), cdf_.size() - 1);
        pmf = selection_pmf(k, from, normal);
    }
    const EmissiveTriangle& tri = triangles_[k];
    if (tri.area <= 0.0f) return std::nullopt;
    const Vec2 b = sample_uniform_triangle(u);
    ls.p = tri.p0 + b.x * tri.e1 + b.y * tri.e2;
    ls.n = tri.n;
    ls.pdf = (1.0f - p_environment_) * pmf / tri.area;
    const Material& mat = shading_.model().materials[tri.material];
    if (mat.emissive_texture.valid() || mat.alpha_tested()) {  // needs the UV
        SurfacePoint sp = shading_.surface(Hit{0.0f, tri.instance, tri.prim, b.x, b.y});
        sp.p = ls.p;
        ls.radiance = shading_.emitted(sp, glm::normalize(from - ls.p));
        // A ray meets a cut-out or blended emitter only where (or as often as) it is there.
        if (mat.alpha_tested())
            ls.radiance *= alpha_coverage(mat, base_color_alpha(shading_.model(), mat, sp.uv));
    } else {
        const bool front = glm::dot(from - ls.p, tri.n) > 0.0f;
        ls.radiance = front || mat.double_sided ? mat.emission() : Rgb(0.0f);
    }
    return ls;
}

float LightSampler::triangle_pdf_area(uint32_t instance, uint32_t prim, const Vec3& from,
                                      const Vec3& normal) const {
    if (instance >= instance_offset_.size() || instance_offset_[instance] < 0) return 0.0f;
    const std::size_t k = std::size_t(instance_offset_[instance]) + prim;
    const float pmf = selection_pmf(k, from, normal);
    return triangles_[k].area > 0.0f ? (1.0f - p_environment_) * pmf / triangles_[k].area : 0.0f;
}

float LightSampler::environment_pdf(const Vec3& w) const {
    return sun_sky_ ? p_environment_ * sun_sky_->pdf(w) : 0.0f;
}

Rgb LightSampler::environment_radiance(const Vec3& w) const {
    return sun_sky_ ? sun_sky_->radiance(w) : Rgb(0.0f);
}

}  // namespace pathfarm
