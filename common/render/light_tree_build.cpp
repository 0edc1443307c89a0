// Building and refitting the light tree (light_tree.h); light_tree.cpp descends it.
#include "common/render/light_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pathfarm {
namespace {

constexpr int kBuckets = 12;
// From this depth on, nodes split at the median: at most 24 more levels for 16 M emitters,
// so every path fits a 64-bit trail (two bits per wide level, one wide level per two).
constexpr int kBalancedFromDepth = 40;

// M_omega of Conty Estevez & Kulla 2018 (eq. 1, theta_e = pi/2): the solid angle a cone of
// normals of half-angle theta_o may light, weighted by cosine.
double orientation_measure(double cos_o) {
    const double pi = 3.14159265358979323846;
    const double theta_o = std::acos(std::clamp(cos_o, -1.0, 1.0)), sin_o = std::sin(theta_o);
    const double theta_w = std::min(theta_o + pi / 2, pi);
    return 2 * pi * (1 - cos_o) + pi / 2 *
                                      (2 * theta_w * sin_o - std::cos(theta_o - 2 * theta_w) -
                                       2 * theta_o * sin_o + cos_o);
}

// orientation_measure tabulated over cos theta_o in [-1, 1] (the split search evaluates it
// some 60 times per node): linear interpolation, well within what a heuristic needs.
double orientation_measure_fast(float cos_o) {
    constexpr int kSteps = 512;
    static const std::vector<double> table = [] {
        std::vector<double> t(kSteps + 1);
        for (int i = 0; i <= kSteps; ++i)
            t[std::size_t(i)] = orientation_measure(-1.0 + 2.0 * double(i) / kSteps);
        return t;
    }();
    const double x = (std::clamp(double(cos_o), -1.0, 1.0) + 1.0) * 0.5 * kSteps;
    const int i = std::min(kSteps - 1, int(x));
    return table[std::size_t(i)] + (x - i) * (table[std::size_t(i) + 1] - table[std::size_t(i)]);
}

// The surface-area-orientation heuristic (Conty Estevez & Kulla 2018, eq. 3): power times
// M_omega times the box's area. `kr` penalises splitting a long box across its short side.
double orientation_area_cost(const Bounds3f& box, float power, float cos_theta_o, float kr) {
    if (!(power > 0.0f) || box.empty()) return 0.0;
    const Vec3 e = box.extent();
    const double area = 2.0 * (double(e.x) * e.y + double(e.y) * e.z + double(e.z) * e.x);
    return double(power) * orientation_measure_fast(cos_theta_o) * double(kr) * area;
}

int bucket_of(float c, float lower, float extent) {
    return std::min(kBuckets - 1, int(float(kBuckets) * (c - lower) / extent));
}

// What the split search keeps of a group of emitters: cheap to extend by one emitter and to
// merge. The normal cone is estimated from the mean of the axes (its length R: 1 when all
// face one way; cos theta_o ~ 2R - 1), not unioned exactly: the exact union is an acos, a
// rotation and more per emitter per axis per level, which made building 10 000 emitters take
// 120 ms. The nodes' own bounds are exact (union_bounds of their children).
struct GroupSummary {
    Bounds3f box;
    Vec3 axis_sum{0.0f};
    float power = 0.0f;
    int count = 0;

    void add(const LightBounds& b) {
        if (!(b.power > 0.0f)) {
            ++count;
            return;
        }
        box.extend(b.box);
        axis_sum += b.axis * std::max(0.0f, b.cos_theta_o);
        power += b.power;
        ++count;
    }
    void add(const GroupSummary& g) {
        box.extend(g.box);
        axis_sum += g.axis_sum;
        power += g.power;
        count += g.count;
    }
    double cost(float kr) const {
        if (count == 0) return 0.0;
        const float cos_o = 2.0f * glm::length(axis_sum) / float(count) - 1.0f;
        return orientation_area_cost(box, power, cos_o, kr);
    }
};

// The cheapest bucket boundary along `dim` (cost, bucket), or cost infinity when none
// separates anything.
std::pair<double, int> best_bucket_along(std::span<const uint32_t> ids,
                                         std::span<const LightBounds> em,
                                         std::span<const Vec3> centre, const Bounds3f& centroids,
                                         int dim, float kr) {
    const float lower = centroids.lower[dim], extent = centroids.extent()[dim];
    GroupSummary bucket[kBuckets];
    for (uint32_t id : ids)
        bucket[bucket_of(centre[id][dim], lower, extent)].add(em[id]);
    GroupSummary above[kBuckets];
    above[kBuckets - 1] = bucket[kBuckets - 1];
    for (int k = kBuckets - 2; k >= 0; --k) {
        above[k] = bucket[k];
        above[k].add(above[k + 1]);
    }
    std::pair<double, int> best{INFINITY, 0};
    GroupSummary below;
    for (int k = 1; k < kBuckets; ++k) {
        below.add(bucket[k - 1]);
        if (below.count == 0 || below.count == int(ids.size())) continue;
        const double cost = below.cost(kr) + above[k].cost(kr);
        if (cost < best.first) best = {cost, k};
    }
    return best;
}

// Where to split `ids`: the cheapest bucket boundary by the heuristic over the three axes, or
// the median along the widest axis when no boundary separates anything (or deep down).
std::size_t split_ids(std::span<uint32_t> ids, std::span<const LightBounds> em,
                      std::span<const Vec3> centre, int depth) {
    Bounds3f centroids, boxes;
    for (uint32_t id : ids) {
        centroids.extend(centre[id]);
        boxes.extend(em[id].box);
    }
    const Vec3 ce = centroids.extent(), be = boxes.extent();
    const float widest = max_component(be);
    double best = INFINITY;
    int best_dim = -1, best_bucket = 0;
    for (int dim = 0; dim < 3 && depth < kBalancedFromDepth; ++dim) {
        if (!(ce[dim] > 0.0f)) continue;
        const float kr = be[dim] > 0.0f ? widest / be[dim] : 1.0f;
        const auto [cost, bucket] = best_bucket_along(ids, em, centre, centroids, dim, kr);
        if (cost < best) {
            best = cost;
            best_dim = dim;
            best_bucket = bucket;
        }
    }
    if (best_dim >= 0) {
        const auto mid = std::partition(ids.begin(), ids.end(), [&](uint32_t id) {
            return bucket_of(centre[id][best_dim], centroids.lower[best_dim], ce[best_dim]) <
                   best_bucket;
        });
        return std::size_t(mid - ids.begin());
    }
    const int dim = ce.x >= ce.y && ce.x >= ce.z ? 0 : ce.y >= ce.z ? 1 : 2;
    const std::size_t half = ids.size() / 2;
    std::nth_element(ids.begin(), ids.begin() + std::ptrdiff_t(half), ids.end(),
                     [&](uint32_t a, uint32_t b) {
                         const float ca = centre[a][dim], cb = centre[b][dim];
                         return ca < cb || (ca == cb && a < b);
                     });
    return half;
}

// Two consecutive emitters that are one flat polygon, such as the two triangles of a quad
// light: facing one way, and together no larger than 1.5x the larger one's box diagonal.
// Their importance differs by little more than their power, so a leaf holds both and chooses
// between them by power: one level and two importance evaluations less per light sample (the
// whole descent on a scene lit by one quad).
bool one_flat_polygon(const LightBounds& a, const LightBounds& b) {
    if (a.two_sided != b.two_sided || a.cos_theta_o < 1.0f || b.cos_theta_o < 1.0f) return false;
    if (glm::dot(a.axis, b.axis) < 0.9998f || a.box.empty() || b.box.empty()) return false;
    Bounds3f u = a.box;
    u.extend(b.box);
    const auto diag2 = [](const Bounds3f& box) { return glm::dot(box.extent(), box.extent()); };
    return diag2(u) <= 2.25f * std::max(diag2(a.box), diag2(b.box));
}

}  // namespace

// What the tree is built over: single emitters and flat pairs, unit u holding emitters
// first[u] up to first[u + 1].
struct LightTree::Units {
    std::vector<uint32_t> first;
    std::vector<LightBounds> bounds;
    std::vector<Vec3> centre;
    // When the units are clusters: each cluster's nodes' bounds from node_base[c] on, and the
    // emitters their leaves hold.
    std::span<const Cluster> clusters;
    std::vector<LightBounds> node_bounds;
    std::vector<uint32_t> node_base;
    std::span<const LightBounds> emitters;
};

namespace {

// A cluster's nodes' bounds over `emitters`, bottom-up (children follow their parent).
void cluster_bounds(const LightTree::Cluster& c, std::span<const LightBounds> emitters,
                    LightBounds* out) {
    for (uint32_t k = c.end - c.root; k-- > 0;) {
        const LightTree::Node& n = c.tree[c.root + k];
        if (n.bounds.flags & LightTree::kLeaf) {
            const uint32_t e = n.child_or_emitter + c.emitter_offset;
            out[k] = (n.bounds.flags & LightTree::kPair)
                         ? union_bounds(emitters[e], emitters[e + 1])
                         : emitters[e];
        } else {
            out[k] = union_bounds(out[k + 1], out[n.child_or_emitter - c.root]);
        }
    }
}

// The clusters' own subtrees are at most this deep (kClusterUnits leaves): the top level
// above them switches to median splits this much earlier, so every path still fits 64 bits.
constexpr int kClusterDepth = int(LightTree::kClusterUnits) - 1;

}  // namespace

LightTree::LightTree(std::span<const LightBounds> emitters, std::span<const Cluster> clusters) {
    if (clusters.empty()) return;
    trail_.assign(emitters.size(), 0);
    depth_.assign(emitters.size(), 0);
    share_.assign(emitters.size(), 1.0f);
    Units units;
    units.clusters = clusters;
    units.emitters = emitters;
    for (const Cluster& c : clusters) {
        const auto base = uint32_t(units.node_bounds.size());
        units.node_base.push_back(base);
        units.node_bounds.resize(base + (c.end - c.root));
        cluster_bounds(c, emitters, units.node_bounds.data() + base);
        units.bounds.push_back(units.node_bounds[base]);
        units.centre.push_back(units.bounds.back().box.center());
    }
    nodes_.reserve(units.node_bounds.size() + clusters.size());
    full_.reserve(units.node_bounds.size() + clusters.size());
    std::vector<uint32_t> ids(clusters.size());
    std::iota(ids.begin(), ids.end(), 0u);
    build(ids, units, kClusterDepth);
    collapse_all();
}

// Appends cluster c's nodes (its topology, its bounds from `units`), renumbered.
void LightTree::splice(const Units& units, uint32_t c) {
    const Cluster& cluster = units.clusters[c];
    const auto base = uint32_t(nodes_.size());
    const uint32_t count = cluster.end - cluster.root;
    nodes_.resize(base + count);
    full_.resize(base + count);
    for (uint32_t k = 0; k < count; ++k) {
        const Node& src = cluster.tree[cluster.root + k];
        const uint32_t i = base + k;
        nodes_[i].bounds.flags = src.bounds.flags & (kLeaf | kPair);
        const bool leaf = (src.bounds.flags & kLeaf) != 0;
        nodes_[i].child_or_emitter = leaf ? src.child_or_emitter + cluster.emitter_offset
                                          : base + (src.child_or_emitter - cluster.root);
        set_bounds(i, units.node_bounds[units.node_base[c] + k]);
        if (leaf && (src.bounds.flags & kPair))
            set_shares(nodes_[i].child_or_emitter, units.emitters);
    }
}

std::vector<LightTree::Cluster> LightTree::clusters(uint32_t emitter_offset) const {
    if (nodes_.empty()) return {};
    std::vector<uint32_t> leaves(nodes_.size());
    for (std::size_t i = nodes_.size(); i-- > 0;)
        leaves[i] = is_leaf(i) ? 1u : leaves[i + 1] + leaves[nodes_[i].child_or_emitter];
    std::vector<Cluster> out;
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        const uint32_t i = stack.back();
        stack.pop_back();
        if (leaves[i] <= kClusterUnits) {  // a full binary subtree: 2 leaves - 1 nodes
            out.push_back({nodes_, i, i + 2 * leaves[i] - 1, emitter_offset});
            continue;
        }
        stack.push_back(nodes_[i].child_or_emitter);
        stack.push_back(i + 1);
    }
    return out;
}

LightTree::LightTree(std::span<const LightBounds> emitters) {
    if (emitters.empty()) return;
    trail_.assign(emitters.size(), 0);
    depth_.assign(emitters.size(), 0);
    share_.assign(emitters.size(), 1.0f);
    Units units;
    for (std::size_t k = 0; k < emitters.size();) {
        const bool pair = k + 1 < emitters.size() && one_flat_polygon(emitters[k], emitters[k + 1]);
        units.first.push_back(uint32_t(k));
        units.bounds.push_back(pair ? union_bounds(emitters[k], emitters[k + 1]) : emitters[k]);
        units.centre.push_back(units.bounds.back().box.center());
        if (pair) set_shares(uint32_t(k), emitters);
        k += pair ? 2 : 1;
    }
    units.first.push_back(uint32_t(emitters.size()));
    nodes_.reserve(2 * units.bounds.size() - 1);
    full_.reserve(2 * units.bounds.size() - 1);
    std::vector<uint32_t> ids(units.bounds.size());
    std::iota(ids.begin(), ids.end(), 0u);
    build(ids, units, 0);
    collapse_all();
}

uint32_t LightTree::build(std::span<uint32_t> ids, const Units& units, int depth) {
    const auto node = uint32_t(nodes_.size());
    nodes_.push_back({});
    full_.emplace_back();
    if (ids.size() == 1 && !units.clusters.empty()) {
        nodes_.pop_back();
        full_.pop_back();
        splice(units, ids[0]);
        return node;
    }
    if (ids.size() == 1) {
        const uint32_t first = units.first[ids[0]], end = units.first[ids[0] + 1];
        nodes_[node].bounds.flags = kLeaf | (end - first == 2 ? kPair : 0u);
        set_bounds(node, units.bounds[ids[0]]);
        nodes_[node].child_or_emitter = first;
        return node;
    }
    const std::size_t mid = split_ids(ids, units.bounds, units.centre, depth);
    const uint32_t first = build(ids.first(mid), units, depth + 1);
    const uint32_t second = build(ids.subspan(mid), units, depth + 1);
    set_bounds(node, union_bounds(bounds(first), bounds(second)));
    nodes_[node].child_or_emitter = second;
    return node;
}

void LightTree::refit(std::span<const LightBounds> emitters) {
    // Children follow their parent in the array, so one backward pass sees them first.
    for (std::size_t i = nodes_.size(); i-- > 0;) {
        const uint32_t child = nodes_[i].child_or_emitter;
        if (is_leaf(i))
            set_leaf(i, emitters);
        else
            set_bounds(i, union_bounds(full_[i + 1], full_[child]));
    }
    refill_wide();
}

void LightTree::set_leaf(std::size_t i, std::span<const LightBounds> emitters) {
    const uint32_t e = nodes_[i].child_or_emitter;
    if (!(nodes_[i].bounds.flags & kPair)) {
        set_bounds(i, emitters[e]);
        return;
    }
    set_bounds(i, union_bounds(emitters[e], emitters[e + 1]));
    set_shares(e, emitters);
}

void LightTree::set_shares(uint32_t e, std::span<const LightBounds> emitters) {
    const float a = std::max(0.0f, emitters[e].power), b = std::max(0.0f, emitters[e + 1].power);
    share_[e] = a + b > 0.0f ? a / (a + b) : 0.5f;
    share_[e + 1] = 1.0f - share_[e];
}

double LightTree::cost() const {
    double total = 0.0;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
        if (!is_leaf(i))
            total +=
                orientation_area_cost(full_[i].box, full_[i].power, full_[i].cos_theta_o, 1.0f);
    return total;
}

LightBounds LightTree::bounds(std::size_t i) const { return full_[i]; }

void LightTree::set_bounds(std::size_t i, const LightBounds& b) {
    full_[i] = b;
    const uint32_t leaf = nodes_[i].bounds.flags & (kLeaf | kPair);
    nodes_[i].bounds = pack(b);
    nodes_[i].bounds.flags |= leaf;
}

}  // namespace pathfarm
