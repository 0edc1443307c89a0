// --light-sampler auto: the light tree or power sampling, whichever this scene state needs.
//
// The tree pays for itself where emitters differ in what they give a shading point (near or
// far, facing it or not: builtin:many-lights, light-field, default), and costs 1.5-1.7x power's
// time per ray where they do not (builtin:furnace, whose enclosure gives every point of it the
// same light from every element: choosing by area is ideal there). Which case a scene is, is
// read off the scene: at receivers spread over its surfaces, the variance of a one-sample
// estimate of their unshadowed direct light when the emitter is chosen by the tree against by
// power (as light_tree_variance_test.cpp measures it), estimated from a few of the tree's own
// choices so that its cost does not grow with the number of emitters.
#include <algorithm>
#include <cmath>

#include "common/render/light_sampler.h"
#include "common/sampling/rng.h"

namespace pathfarm {
namespace {

// Receiver positions. With other seeds the median over receivers (the whole sum's) moved by
// up to 0.2 on the scenes in docs/rendering.md ("Choosing the light sampler"): 0.13-0.43 on
// those that need the tree, 0.91-0.96 on the furnace.
constexpr int kPositions = 64;
constexpr uint64_t kSeed = 0x6c69676874ull;  // fixed: the choice is a function of the state

}  // namespace

std::vector<LightChoiceReceiver> light_choice_receivers(const ShadingScene& shading) {
    const SceneModel& scene = shading.model();
    std::vector<uint64_t> first(scene.instances.size());
    uint64_t total = 0;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        first[i] = total;
        total += scene.meshes[scene.instances[i].mesh].triangle_count();
    }
    std::vector<LightChoiceReceiver> out;
    if (total == 0) return out;
    Pcg32 rng(kSeed);
    for (int r = 0; r < kPositions; ++r) {
        const uint64_t t =
            std::min<uint64_t>(total - 1, uint64_t(double(rng.next_float()) * double(total)));
        const auto instance =
            std::size_t(std::upper_bound(first.begin(), first.end(), t) - first.begin() - 1);
        Vec3 v[3];
        shading.triangle_vertices(uint32_t(instance), uint32_t(t - first[instance]), v);
        const Vec3 c = glm::cross(v[1] - v[0], v[2] - v[0]);
        const float len = glm::length(c);
        Vec2 b = rng.next_2d();
        if (b.x + b.y > 1.0f) b = Vec2(1.0f) - b;
        if (!(len > 0.0f) || !std::isfinite(len)) continue;
        const Vec3 n = c / len, p = v[0] + b.x * (v[1] - v[0]) + b.y * (v[2] - v[0]);
        // Off the surface by a little more than its rounding, so that it does not see its own
        // triangle edge-on.
        const float offset = 1e-4f * (1.0f + glm::length(p));
        out.push_back({p + offset * n, n});
        out.push_back({p - offset * n, -n});
    }
    return out;
}

// The unshadowed light emitter k gives a receiver, up to a factor common to all emitters:
// its radiance (power over area and sides) times the geometry term at its centroid, the
// distance kept above the triangle's size.
double LightSampler::unshadowed_light(std::size_t k, const Vec3& p, const Vec3& n) const {
    const EmissiveTriangle& e = triangles_[k];
    const Material& m = shading_.model().materials[std::size_t(e.material)];
    const Vec3 d = e.p0 + (e.e1 + e.e2) / 3.0f - p;
    const float d2 = glm::dot(d, d);
    if (!(d2 > 0.0f)) return 0.0;
    const Vec3 w = d / std::sqrt(d2);
    const float out = m.double_sided ? std::abs(glm::dot(e.n, w)) : -glm::dot(e.n, w);
    const float in = glm::dot(n, w);
    if (!(out > 0.0f && in > 0.0f)) return 0.0;
    const double sides = m.double_sided ? 2.0 : 1.0;
    return double(cdf_.pmf(k)) / sides * out * in / std::max(d2, e.area);
}

namespace {

double median(std::vector<double> values) {
    const auto mid = values.begin() + std::ptrdiff_t(values.size() / 2);
    std::nth_element(values.begin(), mid, values.end());
    return *mid;
}

}  // namespace

LightChoice LightSampler::measure_choice() const {
    LightChoice choice;
    if (tree_.empty()) return choice;
    std::vector<double> ratios;
    constexpr int kChoices = LightChoice::kChoicesPerReceiver;
    const std::vector<LightChoiceReceiver> receivers = light_choice_receivers(shading_);
    for (std::size_t i = 0; i < receivers.size(); ++i) {
        const LightChoiceReceiver& r = receivers[i];
        // With w = f / p_tree over the tree's choices: the light's sum is E[w], the tree's
        // second moment E[w^2], power's E[w f / p_power] (importance sampled by the tree, which
        // reaches every emitter that lights the receiver).
        double sum = 0.0, tree_second = 0.0, power_second = 0.0;
        for (int s = 0; s < kChoices; ++s) {
            const float u = (float(s) + 0.5f) / float(kChoices);
            const auto c = tree_.sample(r.p, r.n, u);
            if (!c || !(c->pmf > 0.0f)) continue;
            const double f = unshadowed_light(c->emitter, r.p, r.n);
            const double p_power = cdf_.pmf(c->emitter);
            if (!(f > 0.0) || !(p_power > 0.0)) continue;
            const double w = f / c->pmf;
            sum += w;
            tree_second += w * w;
            power_second += w * f / p_power;
        }
        const double mean = sum / kChoices;
        if (mean > 0.0) {  // else unlit (as far as the tree's choices saw)
            const double by_tree = std::max(0.0, tree_second / kChoices - mean * mean);
            const double by_power = std::max(0.0, power_second / kChoices - mean * mean);
            const double tiny = 1e-9 * mean * mean;
            ratios.push_back(
                by_tree <= tiny && by_power <= tiny ? 1.0 : by_tree / std::max(by_power, tiny));
        }
        // The first look: where its receivers read far from the threshold, the rest would
        // not change the decision (the whole reading is itself within a factor of 3 of the
        // whole sum over every emitter), and most scenes are far from it.
        if (i + 1 == std::size_t(LightChoice::kFirstLook) &&
            ratios.size() >= std::size_t(LightChoice::kFirstLook / 2)) {
            const double first = median(ratios);
            choice.first_look = first < LightChoice::kTreeBelow / LightChoice::kClearFactor ||
                                first > LightChoice::kTreeBelow * LightChoice::kClearFactor;
            if (choice.first_look) break;
        }
    }
    choice.receivers = int(ratios.size());
    if (ratios.empty()) return choice;
    choice.variance_ratio = median(std::move(ratios));
    choice.selection = choice.variance_ratio < LightChoice::kTreeBelow ? LightSelection::tree
                                                                       : LightSelection::power;
    return choice;
}

}  // namespace pathfarm
