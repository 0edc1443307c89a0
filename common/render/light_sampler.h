// Chooses a light for next-event estimation: every emissive triangle is an area light (scenes
// may hold thousands), picked either in proportion to its power or through a light tree by its
// importance to the shading point (light_tree.h), plus the sun/sky when it lights the scene.
// Densities are returned per unit area for triangles and per solid angle for the sky.
#pragma once

#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "common/render/light_topology.h"
#include "common/render/light_tree.h"
#include "common/render/shading_scene.h"
#include "common/render/sun_sky.h"
#include "common/sampling/guided_cdf.h"

namespace pathfarm {

struct LightSample {
    Vec3 p{0.0f};        // point on the light (triangles), or a direction (environment)
    Vec3 n{0.0f};        // front normal of the triangle
    Rgb radiance{0.0f};  // emitted towards the receiver, before visibility
    float pdf = 0.0f;    // includes the selection probability; area or solid-angle measure
    bool environment = false;
    // An environment sample drawn without its radiance (left zero): environment_radiance(p)
    // gives it once a shadow ray has found the sky visible.
    bool radiance_deferred = false;
};

// How an emissive triangle is chosen (--light-sampler tree|power|auto). automatic is asked
// for, never used: a LightSampler resolves it to tree or power for its scene state
// (light_sampler_choice.cpp).
enum class LightSelection : uint8_t { power, tree, automatic };
inline const char* light_selection_name(LightSelection s) {
    return s == LightSelection::tree ? "tree" : s == LightSelection::power ? "power" : "auto";
}
std::optional<LightSelection> parse_light_selection(std::string_view name);

// What --light-sampler auto read off a scene state: at receivers spread over the scene's
// triangles, the variance of choosing an emitter by the tree over that by power, for a
// one-sample estimate of the receiver's unshadowed direct light (the median over receivers).
struct LightChoice {
    LightSelection selection = LightSelection::power;
    double variance_ratio = 1.0;
    int receivers = 0;        // those some emitter lights, of those read
    bool first_look = false;  // decided after kFirstLook receivers (the reading was clear)
    // The tree costs up to 1.7x power's time per ray (builtin:furnace, docs/performance.md):
    // below 1 / 1.7 of power's variance it is worth that even where the whole error is the
    // light's choice.
    static constexpr double kTreeBelow = 0.6;
    // Tree choices per receiver behind each receiver's reading.
    static constexpr int kChoicesPerReceiver = 32;
    // Receivers (of 128) read before deciding early: when at least half of them are lit and
    // their median lies beyond kClearFactor either side of kTreeBelow.
    static constexpr int kFirstLook = 32;
    static constexpr double kClearFactor = 2.5;
};

// Where LightChoice reads a scene: points uniform over its triangles by count (not by area:
// detail is where the triangles are) from a fixed seed, each looked at from both sides, just off
// the surface.
struct LightChoiceReceiver {
    Vec3 p, n;
};
std::vector<LightChoiceReceiver> light_choice_receivers(const ShadingScene& shading);

class LightSampler {
public:
    // Instances flagged in `excluded` (indexed like SceneModel::instances) are not sampled:
    // emitters that cannot contribute (SealedEmitters).
    // From kClusteredFrom emitters on, the light tree keeps each emissive mesh's topology
    // (light_topology.h): from `topology` when given (a backend's, kept across states: a moved
    // emitter costs a refit and a small top level), else built here; the tree is the same
    // either way. Below, a build over all emitters costs little and samples better (measured:
    // docs/performance.md, "Many lights").
    explicit LightSampler(const ShadingScene& shading, const std::vector<bool>& excluded = {},
                          LightSelection selection = LightSelection::power,
                          LightTopologyCache* topology = nullptr);
    static constexpr std::size_t kClusteredFrom = 4096;

    bool empty() const { return triangles_.empty() && !sun_sky_; }
    // Samples a light as seen from a receiver at `from` with geometric normal `normal` (zero:
    // none, e.g. a medium). u_select chooses, u positions. With `defer_environment`, a sun/sky
    // sample comes without its radiance (LightSample::radiance_deferred): the Preetham sky's
    // six exponentials and an arc cosine are then spent only where its shadow ray escapes.
    std::optional<LightSample> sample(const Vec3& from, const Vec3& normal, float u_select, Vec2 u,
                                      bool defer_environment = false) const;
    // Selection probability times 1/area for the emissive triangle (instance, prim) as
    // sample() at (from, normal) chooses it; 0 if it is not a light.
    float triangle_pdf_area(uint32_t instance, uint32_t prim, const Vec3& from,
                            const Vec3& normal) const;
    // Selection probability times the sky's solid-angle density for direction w.
    float environment_pdf(const Vec3& w) const;
    Rgb environment_radiance(const Vec3& w) const;
    bool has_environment() const { return sun_sky_ != nullptr; }
    std::size_t triangle_count() const { return triangles_.size(); }

    // The distribution itself, for backends that sample it on a device.
    struct EmissiveTriangle {
        uint32_t instance, prim;
        int material;
        Vec3 p0, e1, e2, n;
        float area;
    };
    const std::vector<EmissiveTriangle>& triangles() const { return triangles_; }
    const std::vector<float>& cdf() const { return cdf_.values(); }  // normalised cumulative power
    const std::vector<uint32_t>& cdf_guide() const { return cdf_.guide(); }  // GuidedCdf::guide
    // The selection in use (tree or power), and the one asked for (automatic too).
    LightSelection selection() const { return selection_; }
    LightSelection requested() const { return requested_; }
    // How automatic chose (the default LightChoice when tree or power was asked for).
    const LightChoice& choice() const { return choice_; }
    const LightTree& tree() const { return tree_; }  // empty unless selection() is tree
    float environment_probability() const { return p_environment_; }
    const SunSky* sun_sky() const { return sun_sky_.get(); }
    // Index of the instance's first triangle in triangles(), or -1 if it emits nothing.
    int64_t first_light_of(uint32_t instance) const { return instance_offset_[instance]; }

private:
    // The selection probability of emitter k for a receiver at (from, normal).
    float selection_pmf(std::size_t k, const Vec3& from, const Vec3& normal) const;

    double unshadowed_light(std::size_t k, const Vec3& p, const Vec3& n) const;
    // Tree or power for this state, from tree_ (light_sampler_choice.cpp).
    LightChoice measure_choice() const;

    // The light tree over `bounds`: each emissive mesh's clusters, a top level over them.
    void make_tree(const std::vector<LightBounds>& bounds, LightTopologyCache& topology);

    const ShadingScene& shading_;
    LightSelection requested_, selection_;
    LightChoice choice_;
    LightTree tree_;
    std::vector<EmissiveTriangle> triangles_;
    GuidedCdf cdf_;                         // cumulative power, normalised to 1
    std::vector<int64_t> instance_offset_;  // first light of each instance, or -1
    std::unique_ptr<SunSky> sun_sky_;
    float p_environment_ = 0.0f;
};

}  // namespace pathfarm
