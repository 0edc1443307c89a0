// The light tree over random emitter sets (size, scale, orientation, power, one- or two-sided,
// clusters of panels facing one way as in builtin:many-lights), seen from random receivers:
// its selection probabilities sum to one, sample() reports the probability pmf() computes, no
// emitter that can light a receiver has probability zero (that would bias next-event
// estimation), and a refit keeps every lit emitter inside its ancestors' boxes and cones.
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "common/render/light_tree.h"
#include "tests/support/random_geometry.h"

namespace pathfarm::light_tree_test {
namespace {

using test::random_direction;

struct Emitter {
    Vec3 p[3];
    Vec3 normal;
    float power;
    bool two_sided;
    LightBounds bounds() const {
        return triangle_light_bounds(p[0], p[1], p[2], normal, power, two_sided);
    }
};

Emitter make_triangle(std::mt19937& rng, const Vec3& centre, const Vec3& normal, float size,
                      float power, bool two_sided) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const Vec3 t = glm::normalize(
        glm::cross(normal, std::abs(normal.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0)));
    const Vec3 b = glm::cross(normal, t);
    Emitter e{};
    for (Vec3& p : e.p)
        p = centre + size * (u(rng) * t + u(rng) * b);
    // Wind the vertices so the geometric normal is `normal` (the tree takes it as given).
    e.normal = normal;
    e.power = power;
    e.two_sided = two_sided;
    return e;
}

// The two triangles of a quad light (centre c, edges along t and b), in either diagonal.
void add_quad(std::vector<Emitter>& out, const Vec3& c, const Vec3& t, const Vec3& b, float power,
              bool two_sided, bool flip) {
    const Vec3 n = glm::normalize(glm::cross(t, b));
    const Vec3 v[4] = {c - t - b, c + t - b, c + t + b, c - t + b};
    const int tri[2][3] = {{0, 1, flip ? 3 : 2}, {flip ? 1 : 0, 2, 3}};
    for (const auto& k : tri)
        out.push_back(
            {{v[k[0]], v[k[1]], v[k[2]]}, n, power * (0.5f + 0.25f * float(k[2])), two_sided});
}

// A random set: scattered triangles of every orientation plus, in half the sets, a ceiling of
// small panels all facing down, and in every third one quad lights of any orientation (a leaf
// holds both triangles of a quad).
std::vector<Emitter> random_emitters(uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float scale = std::pow(10.0f, -2.0f + 4.0f * u(rng));
    const int scattered = 1 + int(u(rng) * 120.0f);
    std::vector<Emitter> out;
    for (int i = 0; i < scattered; ++i) {
        const Vec3 c = scale * Vec3(u(rng), u(rng), u(rng));
        const float power = u(rng) < 0.1f ? 0.0f : std::pow(10.0f, -3.0f + 6.0f * u(rng));
        out.push_back(make_triangle(rng, c, random_direction(rng), scale * 0.3f * u(rng) + 1e-4f,
                                    power, u(rng) < 0.3f));
    }
    if (seed % 2 == 0)
        for (int i = 0; i < 256; ++i) {
            const Vec3 c = scale * Vec3(float(i % 16) / 16.0f, 1.0f, float(i / 16) / 16.0f);
            out.push_back(
                make_triangle(rng, c, Vec3(0, -1, 0), scale * 0.01f, 1.0f + float(i % 7), false));
        }
    if (seed % 3 == 0)
        for (int i = 0; i < 40; ++i) {
            const Vec3 n = random_direction(rng);
            const Vec3 t = glm::normalize(glm::cross(n, random_direction(rng)));
            const float size = scale * 0.2f * u(rng) + 1e-4f;
            add_quad(out, scale * Vec3(u(rng), u(rng), u(rng)), t * size * (0.2f + u(rng)),
                     glm::cross(n, t) * size, u(rng) < 0.1f ? 0.0f : 1.0f + u(rng), u(rng) < 0.3f,
                     u(rng) < 0.5f);
        }
    return out;
}

std::vector<LightBounds> bounds_of(const std::vector<Emitter>& emitters) {
    std::vector<LightBounds> b;
    for (const Emitter& e : emitters)
        b.push_back(e.bounds());
    return b;
}

// Whether emitter e can send light to p (a receiver with normal n, zero for none), with a
// margin so rounding at grazing angles does not count.
bool can_light(const Emitter& e, const Vec3& p, const Vec3& n) {
    if (!(e.power > 0.0f)) return false;
    const Vec3 c = (e.p[0] + e.p[1] + e.p[2]) / 3.0f;
    const Vec3 d = p - c;
    const float dist = glm::length(d);
    if (dist <= 0.0f) return false;
    const float facing = glm::dot(d, e.normal) / dist;
    if (e.two_sided ? std::abs(facing) < 1e-3f : facing < 1e-3f) return false;
    return n == Vec3(0.0f) || std::abs(glm::dot(d, n)) > 1e-3f * dist;
}

// A receiver near the emitters: inside their bounds, just off one of them, or far away.
void random_receiver(std::mt19937& rng, const std::vector<Emitter>& emitters, Vec3& p, Vec3& n) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Bounds3f box;
    for (const Emitter& e : emitters)
        for (const Vec3& v : e.p)
            box.extend(v);
    const float kind = u(rng);
    if (kind < 0.5f) {
        p = box.lower + Vec3(u(rng), u(rng), u(rng)) * box.extent() * 1.2f;
    } else if (kind < 0.8f) {
        const Emitter& e = emitters[std::size_t(u(rng) * float(emitters.size())) % emitters.size()];
        p = e.p[0] + e.normal * (0.01f * max_component(box.extent()) * u(rng));
    } else {
        p = box.center() + random_direction(rng) * 50.0f * max_component(box.extent());
    }
    n = u(rng) < 0.2f ? Vec3(0.0f) : random_direction(rng);
}

TEST(LightTree, ProbabilitiesSumToOneMatchSamplingAndMissNoEmitter) {
    for (uint32_t seed = 1; seed <= 40; ++seed) {
        const std::vector<Emitter> emitters = random_emitters(seed);
        const LightTree tree(bounds_of(emitters));
        ASSERT_EQ(tree.emitter_count(), emitters.size());
        std::mt19937 rng(seed * 7919u);
        for (int r = 0; r < 12; ++r) {
            Vec3 p, n;
            random_receiver(rng, emitters, p, n);
            double sum = 0.0;
            for (uint32_t e = 0; e < emitters.size(); ++e) {
                const float pmf = tree.pmf(p, n, e);
                sum += pmf;
                if (can_light(emitters[e], p, n)) {
                    ASSERT_GT(pmf, 0.0f) << "seed " << seed << " receiver " << r << ": emitter "
                                         << e << " lights it but is never chosen";
                }
            }
            ASSERT_NEAR(sum, 1.0, 1e-4) << "seed " << seed << " receiver " << r;
            for (int k = 0; k < 64; ++k) {
                const auto choice = tree.sample(p, n, (float(k) + 0.5f) / 64.0f);
                ASSERT_TRUE(choice.has_value());
                const float pmf = tree.pmf(p, n, choice->emitter);
                ASSERT_NEAR(choice->pmf, pmf, 1e-5f * pmf) << "seed " << seed;
            }
        }
    }
}

TEST(LightTree, SamplingFrequenciesFollowThePmf) {
    const std::vector<Emitter> emitters = random_emitters(6);
    const LightTree tree(bounds_of(emitters));
    std::mt19937 rng(99);
    for (int r = 0; r < 4; ++r) {
        Vec3 p, n;
        random_receiver(rng, emitters, p, n);
        constexpr int kDraws = 1 << 16;
        std::vector<int> count(emitters.size(), 0);
        for (int k = 0; k < kDraws; ++k)
            if (const auto c = tree.sample(p, n, (float(k) + 0.5f) / float(kDraws))) {
                ++count[c->emitter];
            }
        for (uint32_t e = 0; e < emitters.size(); ++e)  // stratified: within a few strata
            EXPECT_NEAR(double(count[e]) / kDraws, tree.pmf(p, n, e), 64.0 / kDraws)
                << "emitter " << e;
    }
}

// What the descent reads in a wide node's slot is its binary node's bounds, packed (the flags'
// container bits aside): after a build, and after a refit that only refills the slots.
bool slot_holds(const LightTree::WideNode& w, int slot, const LightBounds& b) {
    PackedLightBounds seen = slot_bounds(w, slot), want = pack(b);
    seen.flags &= kPackedTwoSided;
    want.flags &= kPackedTwoSided;
    return std::memcmp(&seen, &want, sizeof(seen)) == 0;
}

// Every emitter's path from the wide root (its trail) ends at its own leaf, and every slot on
// the way bounds it: box, cone and power; the slots hold those bounds.
void expect_ancestors_bound(const LightTree& tree, const std::vector<Emitter>& emitters,
                            uint32_t seed) {
    for (uint32_t e = 0; e < emitters.size(); ++e) {
        const LightBounds own = emitters[e].bounds();
        std::size_t node = 0;
        for (int d = 0;; ++d) {
            const int slot = int((tree.trails()[e] >> (2 * d)) & 3u);
            const LightBounds b = tree.bounds(node, slot);
            if (own.power > 0.0f) {
                const float slack = 1e-5f * (1.0f + max_component(glm::abs(b.box.upper)));
                EXPECT_TRUE(glm::all(glm::lessThanEqual(b.box.lower, own.box.lower + slack)) &&
                            glm::all(glm::greaterThanEqual(b.box.upper, own.box.upper - slack)))
                    << "seed " << seed << " emitter " << e << " outside its ancestor's box";
                EXPECT_GE(glm::dot(own.axis, b.axis), b.cos_theta_o - 1e-6f)
                    << "seed " << seed << " emitter " << e << " outside its ancestor's cone";
                EXPECT_GE(b.power, own.power * (1.0f - 1e-5f));
                EXPECT_TRUE(b.two_sided || !own.two_sided);
            }
            const LightTree::WideNode& w = tree.wide_nodes()[node];
            EXPECT_TRUE(slot_holds(w, slot, b))
                << "seed " << seed << " emitter " << e << ": stale wide slot at depth " << d;
            if (w.flags[slot] & LightTree::kLeaf) {
                const uint32_t held = w.child[slot];
                const bool pair = (w.flags[slot] & LightTree::kPair) != 0;
                ASSERT_TRUE(held == e || (pair && held + 1 == e));
                ASSERT_EQ(d + 1, tree.depths()[e]);
                break;
            }
            ASSERT_LT(d, LightTree::kMaxDepth / 2);
            node = w.child[slot];
        }
    }
}

TEST(LightTree, RefitKeepsEveryEmitterInsideItsAncestors) {
    for (uint32_t seed = 1; seed <= 30; ++seed) {
        std::vector<Emitter> emitters = random_emitters(seed);
        LightTree tree(bounds_of(emitters));
        expect_ancestors_bound(tree, emitters, seed);
        const double built = tree.cost();
        tree.refit(bounds_of(emitters));
        EXPECT_NEAR(tree.cost(), built, 1e-6 * built) << "a refit in place changes nothing";
        const std::vector<LightTree::WideNode> before_moves = tree.wide_nodes();
        const std::vector<LightBounds> unmoved = bounds_of(emitters);
        // Move, turn and switch: lights on and off, some far away.
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        for (Emitter& e : emitters) {
            const Vec3 shift = random_direction(rng) * (u(rng) < 0.1f ? 10.0f : 0.1f) *
                               glm::length(e.p[1] - e.p[0] + Vec3(1e-3f));
            for (Vec3& v : e.p)
                v += shift;
            if (u(rng) < 0.3f) e.normal = random_direction(rng);
            e.power = u(rng) < 0.15f ? 0.0f : (e.power > 0.0f ? e.power : 1.0f) * 2.0f * u(rng);
        }
        tree.refit(bounds_of(emitters));
        expect_ancestors_bound(tree, emitters, seed);
        Vec3 p, n;
        random_receiver(rng, emitters, p, n);
        double sum = 0.0;
        for (uint32_t e = 0; e < emitters.size(); ++e)
            sum += tree.pmf(p, n, e);
        EXPECT_NEAR(sum, 1.0, 1e-4) << "seed " << seed;
        tree.refit(unmoved);  // back where they were: the same wide nodes, bit for bit
        ASSERT_EQ(tree.wide_nodes().size(), before_moves.size());
        EXPECT_EQ(std::memcmp(tree.wide_nodes().data(), before_moves.data(),
                              before_moves.size() * sizeof(LightTree::WideNode)),
                  0)
            << "seed " << seed;
    }
}

TEST(LightTree, AQuadLightIsOneLeafChosenByPower) {
    std::vector<Emitter> one;
    add_quad(one, Vec3(0, 2, 0), Vec3(0.3f, 0, 0), Vec3(0, 0, 0.2f), 1.0f, false, false);
    const LightTree tree(bounds_of(one));
    ASSERT_EQ(tree.nodes().size(), 1u) << "no importance to evaluate under one quad light";
    const float total = one[0].power + one[1].power;
    EXPECT_FLOAT_EQ(tree.pmf(Vec3(0.5f), Vec3(0, 1, 0), 0), one[0].power / total);
    EXPECT_FLOAT_EQ(tree.pmf(Vec3(0.5f), Vec3(0, 1, 0), 1), one[1].power / total);
    // Every quad of a random set shares a leaf; the ceiling's separate panels never pair.
    for (uint32_t seed = 3; seed <= 30; seed += 3) {
        const std::vector<Emitter> emitters = random_emitters(seed);
        const LightTree mixed(bounds_of(emitters));
        const std::size_t quads_from = emitters.size() - 80;
        for (std::size_t e = 0; e < emitters.size(); ++e) {
            const bool quad = e >= quads_from;
            const std::size_t partner = quad ? (e - quads_from) % 2 ? e - 1 : e + 1 : e;
            if (!quad) {
                EXPECT_EQ(mixed.leaf_shares()[e], 1.0f) << "seed " << seed << " emitter " << e;
                continue;
            }
            EXPECT_EQ(mixed.trails()[e], mixed.trails()[partner]) << "seed " << seed;
            EXPECT_EQ(mixed.depths()[e], mixed.depths()[partner]) << "seed " << seed;
            EXPECT_FLOAT_EQ(mixed.leaf_shares()[e] + mixed.leaf_shares()[partner], 1.0f);
        }
    }
}

// The descent weighs four slots at once (SIMD); each weight must be importance() and estimate()
// of that slot: random bounds (inside and outside their spheres, two-sided, empty, tiny and
// huge, mixed one- and two-sided power, single emitters and groups), random receivers with and
// without a normal.
TEST(LightTree, WideImportanceAndEstimateAreTheScalarOnesOfEachSlot) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 20000; ++i) {
        LightTree::WideNode w{};
        const float scale = std::pow(10.0f, -3.0f + 6.0f * u(rng));
        for (int k = 0; k < LightTree::kWidth; ++k) {
            const Vec3 c = scale * Vec3(u(rng), u(rng), u(rng)), a = random_direction(rng);
            for (int d = 0; d < 3; ++d) {
                w.center[d][k] = c[d];
                w.axis[d][k] = a[d];
            }
            w.radius2[k] = scale * scale * u(rng) * u(rng);
            w.cos_theta_o[k] = u(rng) < 0.3f ? 1.0f : 2.0f * u(rng) - 1.0f;
            w.sin_theta_o[k] = std::sqrt(1.0f - w.cos_theta_o[k] * w.cos_theta_o[k]);
            w.power[k] = u(rng) < 0.15f ? 0.0f : std::pow(10.0f, -3.0f + 6.0f * u(rng));
            w.flags[k] = (u(rng) < 0.3f ? kPackedTwoSided : 0u) |
                         (u(rng) < 0.5f ? LightTree::kLeaf : 0u) |
                         (u(rng) < 0.3f ? LightTree::kPair : 0u);
            const Vec3 m = u(rng) * random_direction(rng);
            for (int d = 0; d < 3; ++d)
                w.mean_normal[d][k] = m[d];
            w.diffuse_share[k] = u(rng) < 0.5f ? 0.0f : u(rng);
        }
        const Vec3 p = scale * Vec3(2.0f * u(rng), 2.0f * u(rng), 2.0f * u(rng)) - Vec3(scale / 2);
        const Vec3 n = u(rng) < 0.2f ? Vec3(0.0f) : random_direction(rng);
        float wide[LightTree::kWidth], guess[LightTree::kWidth];
        wide_weights(w, p, n, wide, guess);
        for (int k = 0; k < LightTree::kWidth; ++k) {
            const float scalar = importance(slot_bounds(w, k), p, n);
            ASSERT_NEAR(wide[k], scalar, 1e-6f * scalar) << "case " << i << " slot " << k;
            const bool single =
                (w.flags[k] & (LightTree::kLeaf | LightTree::kPair)) == LightTree::kLeaf;
            const float estimated =
                scalar > 0.0f ? estimate(slot_bounds(w, k), p, n, single) : 0.0f;
            ASSERT_NEAR(guess[k], estimated, 1e-5f * estimated) << "case " << i << " slot " << k;
            if (scalar == 0.0f) {
                ASSERT_EQ(guess[k], 0.0f) << "case " << i << " slot " << k;
            }
        }
    }
}

TEST(LightTree, UnionOfConesHoldsBoth) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 a = random_direction(rng), b = random_direction(rng);
        const float cos_a = u(rng), cos_b = i % 3 == 0 ? 1.0f : u(rng);
        Vec3 axis;
        float cos_o;
        union_cone(a, cos_a, b, cos_b, axis, cos_o);
        // Both cones' edges (a sample of directions on each rim) lie inside the union.
        for (const auto& [w, c] : {std::pair{a, cos_a}, std::pair{b, cos_b}}) {
            const Vec3 t = glm::normalize(glm::cross(w, random_direction(rng)));
            const float s = std::sqrt(std::max(0.0f, 1.0f - c * c));
            for (int k = 0; k < 16; ++k) {
                const float phi = 2.0f * kPi * float(k) / 16.0f;
                const Vec3 rim = c * w + s * (std::cos(phi) * t + std::sin(phi) * glm::cross(w, t));
                EXPECT_GE(glm::dot(glm::normalize(rim), axis), cos_o - 1e-5f) << "case " << i;
            }
        }
    }
}

}  // namespace
}  // namespace pathfarm::light_tree_test
