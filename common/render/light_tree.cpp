// Descending the light tree (light_tree.h): the binary tree collapsed to four children per
// node, all four weighed by importance in one SIMD evaluation; light_tree_build.cpp builds and
// refits the binary tree.
#include "common/render/light_tree.h"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "common/math/float_util.h"

namespace pathfarm {
namespace {

bool distant(const float center[3], float radius2, float cos_theta_o, const Vec3& p) {
    const Vec3 d(p.x - center[0], p.y - center[1], p.z - center[2]);
    return radius2 < LightTree::kDistantSin2 * glm::dot(d, d) &&
           cos_theta_o > LightTree::kDistantCos;
}

bool distant(const LightTree::WideNode& w, int k, const Vec3& p) {
    const float c[3] = {w.center[0][k], w.center[1][k], w.center[2][k]};
    return distant(c, w.radius2[k], w.cos_theta_o[k], p);
}

}  // namespace

PackedLightBounds slot_bounds(const LightTree::WideNode& w, int k) {
    PackedLightBounds b{};
    for (int a = 0; a < 3; ++a) {
        b.center[a] = w.center[a][k];
        b.axis[a] = w.axis[a][k];
    }
    b.radius2 = w.radius2[k];
    b.cos_theta_o = w.cos_theta_o[k];
    b.sin_theta_o = w.sin_theta_o[k];
    b.power = w.power[k];
    b.flags = w.flags[k];
    for (int a = 0; a < 3; ++a)
        b.mean_normal[a] = w.mean_normal[a][k];
    b.diffuse_share = w.diffuse_share[k];
    return b;
}

#if defined(__SSE2__)
namespace {

__m128 select(__m128 mask, __m128 a, __m128 b) {
    return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}
__m128 safe_sqrt(__m128 x) { return _mm_sqrt_ps(_mm_max_ps(_mm_setzero_ps(), x)); }
__m128 dot(__m128 ax, __m128 ay, __m128 az, __m128 bx, __m128 by, __m128 bz) {
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(ax, bx), _mm_mul_ps(ay, by)), _mm_mul_ps(az, bz));
}
__m128 abs_value(__m128 x) { return _mm_and_ps(x, _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff))); }
__m128 load(const float (&v)[4]) { return _mm_loadu_ps(v); }
// Lanes whose flags hold `value` in the bits `mask`.
__m128 flags_equal(const uint32_t (&flags)[4], uint32_t mask, uint32_t value) {
    const __m128i f = _mm_loadu_si128(reinterpret_cast<const __m128i*>(flags));
    return _mm_castsi128_ps(
        _mm_cmpeq_epi32(_mm_and_si128(f, _mm_set1_epi32(int(mask))), _mm_set1_epi32(int(value))));
}

// What importance() and estimate() share: from each slot's centre to p, and the receiver's
// cosine towards the centre (1 without a normal).
struct Lanes {
    __m128 tx, ty, tz, dist2, inv_dist, floor2, cos_i;
    bool receiver;
};

Lanes lanes(const LightTree::WideNode& w, const Vec3& p, const Vec3& n) {
    Lanes l;
    l.tx = _mm_sub_ps(_mm_set1_ps(p.x), load(w.center[0]));
    l.ty = _mm_sub_ps(_mm_set1_ps(p.y), load(w.center[1]));
    l.tz = _mm_sub_ps(_mm_set1_ps(p.z), load(w.center[2]));
    l.dist2 = dot(l.tx, l.ty, l.tz, l.tx, l.ty, l.tz);
    l.inv_dist = _mm_and_ps(_mm_cmpgt_ps(l.dist2, _mm_setzero_ps()),
                            _mm_div_ps(_mm_set1_ps(1.0f), _mm_sqrt_ps(l.dist2)));
    l.floor2 = _mm_max_ps(_mm_max_ps(l.dist2, _mm_mul_ps(_mm_set1_ps(0.25f), load(w.radius2))),
                          _mm_set1_ps(1e-20f));
    l.receiver = n.x != 0.0f || n.y != 0.0f || n.z != 0.0f;
    l.cos_i = _mm_set1_ps(1.0f);
    if (l.receiver)
        l.cos_i = _mm_mul_ps(
            abs_value(dot(l.tx, l.ty, l.tz, _mm_set1_ps(n.x), _mm_set1_ps(n.y), _mm_set1_ps(n.z))),
            l.inv_dist);
    return l;
}

// importance() lane by lane, the same operations in the same order, branches as selects; the
// caller zeroes the lanes importance() would leave early (cos_x not positive).
__m128 bound_lanes(const LightTree::WideNode& w, const Lanes& l, __m128 axis_cos, __m128& cos_x) {
    const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
    const __m128 r2 = load(w.radius2);
    const __m128 outside = _mm_cmpgt_ps(l.dist2, r2);
    const __m128 sin2 = _mm_mul_ps(_mm_mul_ps(r2, l.inv_dist), l.inv_dist);
    const __m128 sin_b = _mm_and_ps(outside, _mm_sqrt_ps(sin2));
    const __m128 cos_b = select(outside, safe_sqrt(_mm_sub_ps(one, sin2)), _mm_set1_ps(-1.0f));
    const __m128 cos_w = select(flags_equal(w.flags, kPackedTwoSided, kPackedTwoSided),
                                abs_value(axis_cos), axis_cos);
    const __m128 cos_o = load(w.cos_theta_o), sin_o = load(w.sin_theta_o);
    const __m128 outside_cone = _mm_cmplt_ps(cos_w, cos_o);
    const __m128 sin_w = safe_sqrt(_mm_sub_ps(one, _mm_mul_ps(cos_w, cos_w)));
    const __m128 cos_wo =
        select(outside_cone, _mm_add_ps(_mm_mul_ps(cos_w, cos_o), _mm_mul_ps(sin_w, sin_o)), one);
    const __m128 sin_wo = select(
        outside_cone,
        _mm_max_ps(zero, _mm_sub_ps(_mm_mul_ps(sin_w, cos_o), _mm_mul_ps(cos_w, sin_o))), zero);
    cos_x = select(_mm_cmpge_ps(cos_wo, cos_b), one,
                   _mm_add_ps(_mm_mul_ps(cos_wo, cos_b), _mm_mul_ps(sin_wo, sin_b)));
    const __m128 result = _mm_div_ps(_mm_mul_ps(load(w.power), cos_x), l.floor2);
    if (!l.receiver) return result;
    const __m128 sin_i = safe_sqrt(_mm_sub_ps(one, _mm_mul_ps(l.cos_i, l.cos_i)));  // best cosine
    return _mm_mul_ps(
        result, select(_mm_cmplt_ps(l.cos_i, cos_b),
                       _mm_add_ps(_mm_mul_ps(l.cos_i, cos_b), _mm_mul_ps(sin_i, sin_b)), one));
}

// estimate() lane by lane: the one-sided emitters' mean cosine plus the diffuse share; a slot
// that is one two-sided emitter emits |cos| (its diffuse share is one half).
__m128 estimate_lanes(const LightTree::WideNode& w, const Lanes& l, __m128 axis_cos) {
    const __m128 single =
        flags_equal(w.flags, LightTree::kLeaf | LightTree::kPair, LightTree::kLeaf);
    const __m128 spread =
        select(single, _mm_mul_ps(_mm_set1_ps(2.0f), abs_value(axis_cos)), _mm_set1_ps(1.0f));
    const __m128 one_sided = _mm_mul_ps(dot(load(w.mean_normal[0]), load(w.mean_normal[1]),
                                            load(w.mean_normal[2]), l.tx, l.ty, l.tz),
                                        l.inv_dist);
    const __m128 emitted = _mm_add_ps(_mm_max_ps(_mm_setzero_ps(), one_sided),
                                      _mm_mul_ps(load(w.diffuse_share), spread));
    const __m128 result = _mm_div_ps(_mm_mul_ps(load(w.power), emitted), l.floor2);
    return l.receiver ? _mm_mul_ps(result, l.cos_i) : result;
}

}  // namespace

// importance() and estimate() (light_bounds.h) for the four slots at once; they share the
// direction and distance to p. Lanes importance() would leave early are zeroed in both.
void wide_weights(const LightTree::WideNode& w, const Vec3& p, const Vec3& n, float bound[4],
                  float guess[4]) {
    const Lanes l = lanes(w, p, n);
    const __m128 axis_cos = _mm_mul_ps(
        dot(load(w.axis[0]), load(w.axis[1]), load(w.axis[2]), l.tx, l.ty, l.tz), l.inv_dist);
    __m128 cos_x;
    const __m128 result = bound_lanes(w, l, axis_cos, cos_x);
    const __m128 estimated = estimate_lanes(w, l, axis_cos);
    const __m128 zero = _mm_setzero_ps(), infinity = _mm_set1_ps(INFINITY);
    const __m128 valid =
        _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(load(w.power), zero), _mm_cmpgt_ps(cos_x, zero)),
                   _mm_cmplt_ps(result, infinity));
    _mm_storeu_ps(bound, _mm_and_ps(valid, result));
    _mm_storeu_ps(guess,
                  _mm_and_ps(_mm_and_ps(valid, _mm_cmplt_ps(estimated, infinity)), estimated));
}
#else
void wide_weights(const LightTree::WideNode& w, const Vec3& p, const Vec3& n, float bound[4],
                  float guess[4]) {
    for (int k = 0; k < LightTree::kWidth; ++k) {
        bound[k] = importance(slot_bounds(w, k), p, n);
        // A slot holding one emitter (a leaf, not a pair): its two-sided emission is exact.
        const bool single =
            (w.flags[k] & (LightTree::kLeaf | LightTree::kPair)) == LightTree::kLeaf;
        guess[k] = bound[k] > 0.0f ? estimate(slot_bounds(w, k), p, n, single) : 0.0f;
    }
}
#endif

// Slot k of a wide node as the binary node's packed bounds (its flags included).
void LightTree::fill_slot(WideNode& w, int k, const PackedLightBounds& s) {
    for (int a = 0; a < 3; ++a) {
        w.center[a][k] = s.center[a];
        w.axis[a][k] = s.axis[a];
        w.mean_normal[a][k] = s.mean_normal[a];
    }
    w.radius2[k] = s.radius2;
    w.cos_theta_o[k] = s.cos_theta_o;
    w.sin_theta_o[k] = s.sin_theta_o;
    w.power[k] = s.power;
    w.diffuse_share[k] = s.diffuse_share;
    w.flags[k] = s.flags;
}

uint32_t LightTree::collapse(uint32_t b, int depth, uint64_t trail) {
    const auto at = uint32_t(wide_.size());
    wide_.push_back({});
    wide_source_.push_back({kNoSource, kNoSource, kNoSource, kNoSource});
    uint32_t slots[kWidth];
    int count = 0;
    if (is_leaf(b)) {  // a tree of one leaf
        slots[count++] = b;
    } else {
        for (const uint32_t c : {b + 1, nodes_[b].child_or_emitter}) {
            if (is_leaf(c)) {
                slots[count++] = c;
            } else {
                slots[count++] = c + 1;
                slots[count++] = nodes_[c].child_or_emitter;
            }
        }
    }
    for (int k = 0; k < count; ++k) {
        const uint32_t g = slots[k];
        const PackedLightBounds& s = nodes_[g].bounds;
        fill_slot(wide_[at], k, s);
        wide_source_[at][std::size_t(k)] = g;
        const uint64_t path = trail | (uint64_t(k) << (2 * depth));
        if (!is_leaf(g)) {
            const uint32_t child = collapse(g, depth + 1, path);  // wide_ may move
            wide_[at].child[k] = child;
            continue;
        }
        const uint32_t e = nodes_[g].child_or_emitter;
        wide_[at].child[k] = e;
        for (uint32_t i = e; i < e + ((s.flags & kPair) ? 2u : 1u); ++i) {
            trail_[i] = path;
            depth_[i] = uint8_t(depth + 1);
        }
    }
    return at;
}

void LightTree::collapse_all() {
    wide_.clear();
    wide_source_.clear();
    if (!nodes_.empty()) collapse(0, 0, 0);
}

// After a refit the topology, the children and the trails are as collapse() left them: only
// the slots' bounds change (a third of the refit's time went to collapsing anew).
void LightTree::refill_wide() {
    for (std::size_t i = 0; i < wide_.size(); ++i)
        for (int k = 0; k < kWidth; ++k)
            if (const uint32_t g = wide_source_[i][std::size_t(k)]; g != kNoSource)
                fill_slot(wide_[i], k, nodes_[g].bounds);
}

LightBounds LightTree::bounds(std::size_t wide_node, int slot) const {
    return full_[wide_source_[wide_node][std::size_t(slot)]];
}

// The four slots' weights and their sum; zero when nothing there emits. The weight is the mean
// of the slot's share of the importance bound and its share of the estimate (light_tree.h), or
// its power where importance says nothing (every bound zero, or below a distant node).
float LightTree::slot_weights(const WideNode& w, const Vec3& p, const Vec3& n, bool& by_power,
                              float weight[kWidth]) const {
    if (!by_power) {
        float guess[kWidth];
        wide_weights(w, p, n, weight, guess);
        const float total = (weight[0] + weight[1]) + (weight[2] + weight[3]);
        if (total > 0.0f) {
            const float guessed = (guess[0] + guess[1]) + (guess[2] + guess[3]);
            if (!(guessed > 0.0f)) return total;
            const float a = 0.5f / total, b = 0.5f / guessed;
            for (int k = 0; k < kWidth; ++k)
                weight[k] = a * weight[k] + b * guess[k];
            return (weight[0] + weight[1]) + (weight[2] + weight[3]);
        }
        by_power = true;
    }
    for (int k = 0; k < kWidth; ++k)
        weight[k] = std::max(0.0f, w.power[k]);
    return (weight[0] + weight[1]) + (weight[2] + weight[3]);
}

std::optional<LightTree::Choice> LightTree::sample(const Vec3& p, const Vec3& n, float u) const {
    // No test of the root's own importance: where it is zero the descent goes by power, and
    // the chosen emitter's zero radiance ends the sample before any ray.
    if (wide_.empty()) return std::nullopt;
    const PackedLightBounds& root = root_bounds();
    bool by_power = is_leaf(0) || distant(root.center, root.radius2, root.cos_theta_o, p);
    float pmf = 1.0f;
    for (uint32_t node = 0;;) {
        const WideNode& w = wide_[node];
        float weight[kWidth];
        const float total = slot_weights(w, p, n, by_power, weight);
        if (!(total > 0.0f)) return std::nullopt;
        const float target = u * total;
        // The first slot whose running sum exceeds the target, counted without a branch per
        // slot (the random choice made those unpredictable): the sums never fall, so the slots
        // whose sums the target reaches come first, and a slot of weight zero is never the
        // first one it does not. Where rounding lets the target reach the last sum: the last
        // slot with weight.
        float below[kWidth];
        below[0] = weight[0];
        for (int k = 1; k < kWidth; ++k)
            below[k] = below[k - 1] + weight[k];
        int slot = int(target >= below[0]) + int(target >= below[1]) + int(target >= below[2]) +
                   int(target >= below[3]);
        if (slot == kWidth)
            for (slot = kWidth - 1; slot > 0 && !(weight[slot] > 0.0f);)
                --slot;
        const float lower = slot > 0 ? below[slot - 1] : 0.0f;
        pmf *= weight[slot] / total;
        u = std::clamp((target - lower) / weight[slot], 0.0f, kOneBelow);
        if (w.flags[slot] & kLeaf) {
            uint32_t emitter = w.child[slot];
            if ((w.flags[slot] & kPair) && !(u < share_[emitter])) ++emitter;
            return Choice{emitter, pmf * share_[emitter]};
        }
        by_power = by_power || distant(w, slot, p);
        node = w.child[slot];
    }
}

float LightTree::pmf(const Vec3& p, const Vec3& n, uint32_t emitter) const {
    if (emitter >= trail_.size()) return 0.0f;
    const uint64_t trail = trail_[emitter];
    const PackedLightBounds& root = root_bounds();
    bool by_power = is_leaf(0) || distant(root.center, root.radius2, root.cos_theta_o, p);
    float pmf = share_[emitter];
    for (uint32_t node = 0, d = 0;; ++d) {
        const WideNode& w = wide_[node];
        float weight[kWidth];
        const float total = slot_weights(w, p, n, by_power, weight);
        if (!(total > 0.0f)) return 0.0f;
        const auto slot = int((trail >> (2 * d)) & 3u);
        if (!(weight[slot] > 0.0f)) return 0.0f;
        pmf *= weight[slot] / total;
        if (w.flags[slot] & kLeaf) return pmf;
        by_power = by_power || distant(w, slot, p);
        node = w.child[slot];
    }
}

}  // namespace pathfarm
