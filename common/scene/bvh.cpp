// Binned SAH construction and refit.
#include "common/scene/bvh.h"

#include <algorithm>
#include <array>

namespace pathfarm {
namespace {

float half_area(const Bounds3f& b) {
    if (b.empty()) return 0.0f;
    const Vec3 e = b.extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

void store(BvhNode& n, const Bounds3f& b) {
    for (int a = 0; a < 3; ++a) {
        n.lower[a] = b.lower[a];
        n.upper[a] = b.upper[a];
    }
}

Bounds3f node_bounds(const BvhNode& n) {
    return Bounds3f{Vec3(n.lower[0], n.lower[1], n.lower[2]),
                    Vec3(n.upper[0], n.upper[1], n.upper[2])};
}

struct Builder {
    const std::vector<Bounds3f>& boxes;
    std::vector<Vec3> centroids;
    Bvh bvh;

    struct Split {
        int axis = -1;
        float position = 0.0f;
        float cost = kInfinity;
    };

    Split find_split(uint32_t begin, uint32_t end, const Bounds3f& centroid_bounds) const {
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            const float lo = centroid_bounds.lower[axis], extent = centroid_bounds.upper[axis] - lo;
            if (!(extent > 0.0f)) continue;
            std::array<Bounds3f, kSahBins> bin_box;
            std::array<uint32_t, kSahBins> bin_count{};
            for (uint32_t i = begin; i < end; ++i) {
                const uint32_t p = bvh.prim_indices[i];
                const int b =
                    std::min(kSahBins - 1, int(kSahBins * ((centroids[p][axis] - lo) / extent)));
                bin_box[b].extend(boxes[p]);
                ++bin_count[b];
            }
            // Sweep: area and count left of each of the kSahBins - 1 planes, then right.
            std::array<float, kSahBins - 1> left_cost{};
            Bounds3f acc;
            uint32_t count = 0;
            for (int b = 0; b < kSahBins - 1; ++b) {
                acc.extend(bin_box[b]);
                count += bin_count[b];
                left_cost[b] = half_area(acc) * float(count);
            }
            acc = Bounds3f{};
            count = 0;
            for (int b = kSahBins - 1; b > 0; --b) {
                acc.extend(bin_box[b]);
                count += bin_count[b];
                const float cost = left_cost[b - 1] + half_area(acc) * float(count);
                if (cost < best.cost)
                    best = Split{axis, lo + extent * float(b) / float(kSahBins), cost};
            }
        }
        return best;
    }

    uint32_t make_leaf(uint32_t node, uint32_t begin, uint32_t end) {
        bvh.nodes[node].first = begin;
        bvh.nodes[node].count = end - begin;
        return node;
    }
};

// Depth-first construction: the left child directly follows its parent, the right child
// follows the left subtree (its index is stored in the parent).
void build_node(Builder& b, uint32_t node, uint32_t begin, uint32_t end, int depth) {
    Bounds3f box, centroid_box;
    for (uint32_t i = begin; i < end; ++i) {
        box.extend(b.boxes[b.bvh.prim_indices[i]]);
        centroid_box.extend(b.centroids[b.bvh.prim_indices[i]]);
    }
    store(b.bvh.nodes[node], box);
    const uint32_t n = end - begin;
    if (n <= uint32_t(kMaxLeafPrims) || depth > 60) {
        b.make_leaf(node, begin, end);
        return;
    }
    const Builder::Split split = b.find_split(begin, end, centroid_box);
    uint32_t mid = begin;
    if (split.axis >= 0) {
        if (split.cost >= half_area(box) * float(n) && n <= 16) {
            b.make_leaf(node, begin, end);
            return;
        }
        mid =
            uint32_t(std::partition(
                         b.bvh.prim_indices.begin() + begin, b.bvh.prim_indices.begin() + end,
                         [&](uint32_t p) { return b.centroids[p][split.axis] < split.position; }) -
                     b.bvh.prim_indices.begin());
    }
    if (mid == begin || mid == end) mid = begin + n / 2;  // coincident centroids: split by count
    const auto left = uint32_t(b.bvh.nodes.size());
    b.bvh.nodes.push_back({});
    build_node(b, left, begin, mid, depth + 1);
    const auto right = uint32_t(b.bvh.nodes.size());
    b.bvh.nodes.push_back({});
    build_node(b, right, mid, end, depth + 1);
    b.bvh.nodes[node].first = right;
    b.bvh.nodes[node].count = 0;
}

Bvh build_from_boxes(const std::vector<Bounds3f>& boxes) {
    Builder b{boxes, {}, {}};
    if (boxes.empty()) return {};
    b.centroids.resize(boxes.size());
    for (std::size_t i = 0; i < boxes.size(); ++i)
        b.centroids[i] = boxes[i].center();
    b.bvh.prim_indices.resize(boxes.size());
    for (uint32_t i = 0; i < boxes.size(); ++i)
        b.bvh.prim_indices[i] = i;
    b.bvh.nodes.reserve(2 * boxes.size() / kMaxLeafPrims + 1);
    b.bvh.nodes.push_back({});
    build_node(b, 0, 0, uint32_t(boxes.size()), 0);
    return std::move(b.bvh);
}

Bounds3f triangle_box(const std::vector<Vec3>& p, const std::vector<uint32_t>& idx, uint32_t t) {
    Bounds3f b;
    for (int k = 0; k < 3; ++k)
        b.extend(p[idx[3 * t + k]]);
    return b;
}

}  // namespace

Bounds3f Bvh::bounds() const { return nodes.empty() ? Bounds3f{} : node_bounds(nodes[0]); }

Bvh build_bvh(const std::vector<Bounds3f>& boxes) { return build_from_boxes(boxes); }

Bvh build_bvh(const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices) {
    std::vector<Bounds3f> boxes(indices.size() / 3);
    for (uint32_t t = 0; t < boxes.size(); ++t)
        boxes[t] = triangle_box(positions, indices, t);
    return build_from_boxes(boxes);
}

void refit_bvh(Bvh& bvh, const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices) {
    for (std::size_t i = bvh.nodes.size(); i-- > 0;) {  // children come after their parents
        BvhNode& n = bvh.nodes[i];
        Bounds3f b;
        if (n.count > 0) {
            for (uint32_t k = n.first; k < n.first + n.count; ++k)
                b.extend(triangle_box(positions, indices, bvh.prim_indices[k]));
        } else {
            b = node_bounds(bvh.nodes[i + 1]);
            b.extend(node_bounds(bvh.nodes[n.first]));
        }
        store(n, b);
    }
}

double sah_cost(const Bvh& bvh) {
    if (bvh.nodes.empty()) return 0.0;
    const double root = half_area(bvh.bounds());
    if (!(root > 0.0)) return 0.0;
    double cost = 0.0;
    for (const BvhNode& n : bvh.nodes) {
        const double a = half_area(node_bounds(n)) / root;
        cost += n.count > 0 ? a * n.count : a;
    }
    return cost;
}

}  // namespace pathfarm
