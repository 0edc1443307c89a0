// A bounding-volume hierarchy over emissive triangles for next-event estimation (Conty Estevez
// & Kulla 2018; pbrt-v4's BVHLightSampler; Cycles' light tree): each node bounds its emitters'
// positions, normals and power (LightBounds), and a shading point descends from the root
// choosing each child in proportion to its importance, so lights that are near and face the
// point are chosen far more often than power alone would. A child's probability is the mean of
// two: by the importance bound, and by an estimate of its light (light_bounds.h), the bound
// keeping every emitter that can light the point reachable, the estimate telling apart groups
// the bound cannot. pmf() retraces an emitter's path
// from the root for multiple importance sampling. Built with the surface-area-orientation
// heuristic over 12 buckets per axis; refit() keeps the topology for moved or switched
// emitters, and cost() tells how much a refit has let the tree's quality degrade.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/render/light_bounds.h"

namespace pathfarm {

class LightTree {
public:
    // The binary tree as built and refitted: an interior node's first child is the next node,
    // its second `child_or_emitter`; a leaf holds one emitter, or with kPair two consecutive
    // ones that form one flat polygon (a quad light's two triangles), chosen between by power:
    // their importance would differ by little more.
    struct Node {
        PackedLightBounds bounds;  // flags: kPackedTwoSided, kLeaf, kPair
        uint32_t child_or_emitter;
    };
    static constexpr uint32_t kLeaf = 2, kPair = 4;
    bool is_leaf(std::size_t node) const { return (nodes_[node].bounds.flags & kLeaf) != 0; }
    static constexpr int kMaxDepth = 64;

    // What a shading point descends: the binary tree collapsed to four children per node
    // (each node's children or grandchildren), their bounds side by side so that one SIMD
    // evaluation weighs all four; half the levels. The OpenCL kernel reads the same layout
    // (device_types.h mirrors it). An unused slot has power zero.
    struct WideNode {
        float center[3][4];
        float radius2[4];
        float axis[3][4];
        float cos_theta_o[4], sin_theta_o[4], power[4];
        float mean_normal[3][4], diffuse_share[4];  // what estimate() reads
        uint32_t flags[4];                          // kPackedTwoSided, kLeaf, kPair
        uint32_t child[4];                          // a wide node, or a leaf's (first) emitter
    };
    static constexpr int kWidth = 4;

    LightTree() = default;
    // One leaf per emitter or flat pair, in the order given (pmf() and the sampled index refer
    // to it).
    explicit LightTree(std::span<const LightBounds> emitters);

    // A subtree of another tree (a mesh's, built once in mesh space: light_topology.h):
    // nodes [root, end) of `tree`, whose leaves' emitters are numbered from emitter_offset here.
    struct Cluster {
        std::span<const Node> tree;
        uint32_t root, end;
        uint32_t emitter_offset;
    };
    // The tree over clusters: each cluster's topology kept, its bounds refitted to `emitters`,
    // and a top level over the clusters built by the same heuristic. A function of the
    // clusters' topology and the emitters' bounds alone, so a state's tree is the same whether
    // its clusters were made just now or frames ago (docs/determinism.md item 6).
    LightTree(std::span<const LightBounds> emitters, std::span<const Cluster> clusters);
    // Subtrees of at most kClusterUnits leaves that together hold every leaf, in node order.
    std::vector<Cluster> clusters(uint32_t emitter_offset) const;
    static constexpr uint32_t kClusterUnits = 16;

    // New bounds for the same emitters (moved, deformed or switched): the topology stays.
    void refit(std::span<const LightBounds> emitters);
    // The surface-area-orientation cost summed over interior nodes: a refit tree's cost over a
    // fresh build's measures how much it has degraded.
    double cost() const;

    struct Choice {
        uint32_t emitter;
        float pmf;
    };
    // Chooses an emitter for a receiver at p with normal n (zero: none). Empty only when no
    // emitter has power; the probabilities of all emitters sum to one.
    std::optional<Choice> sample(const Vec3& p, const Vec3& n, float u) const;
    // The probability sample() chooses `emitter` at (p, n).
    float pmf(const Vec3& p, const Vec3& n, uint32_t emitter) const;

    bool empty() const { return nodes_.empty(); }
    std::size_t emitter_count() const { return trail_.size(); }
    const std::vector<Node>& nodes() const { return nodes_; }
    const std::vector<WideNode>& wide_nodes() const { return wide_; }
    // The whole tree's bounds (the wide root's parent slot, for the distant switch).
    const PackedLightBounds& root_bounds() const { return nodes_[0].bounds; }
    // Per emitter, the path from the wide root: bits 2d and 2d + 1 = the slot taken at depth
    // d; depth = the number of wide nodes on it.
    const std::vector<uint64_t>& trails() const { return trail_; }
    const std::vector<uint8_t>& depths() const { return depth_; }
    // Per emitter, the probability of choosing it once its leaf is chosen (1 unless paired).
    const std::vector<float>& leaf_shares() const { return share_; }
    LightBounds bounds(std::size_t node) const;
    // The full bounds behind a wide node's slot; only for a slot in use (one on an emitter's
    // trail): an unused slot has no binary node behind it.
    LightBounds bounds(std::size_t wide_node, int slot) const;

    // Below a node whose bounding sphere subtends less than this (sin^2 of the half-angle) and
    // whose normals lie within acos(kDistantCos), children are chosen by power: their
    // importance would differ by little more than their power (measured: docs/rendering.md).
    static constexpr float kDistantSin2 = 0.02f, kDistantCos = 0.0f;

private:
    float slot_weights(const WideNode& node, const Vec3& p, const Vec3& n, bool& by_power,
                       float weight[kWidth]) const;
    struct Units;
    uint32_t build(std::span<uint32_t> ids, const Units& units, int depth);
    void splice(const Units& units, uint32_t cluster);
    uint32_t collapse(uint32_t node, int depth, uint64_t trail);
    void collapse_all();
    void refill_wide();  // the wide nodes' bounds from the binary nodes', topology kept
    static void fill_slot(WideNode& w, int k, const PackedLightBounds& s);
    void set_leaf(std::size_t node, std::span<const LightBounds> emitters);
    // The pair e, e + 1's shares of their leaf, by power.
    void set_shares(uint32_t e, std::span<const LightBounds> emitters);
    void set_bounds(std::size_t node, const LightBounds& b);

    std::vector<Node> nodes_;
    std::vector<LightBounds> full_;  // per node, with the box (for refit and cost)
    std::vector<WideNode> wide_;
    static constexpr uint32_t kNoSource = ~0u;               // an unused slot
    std::vector<std::array<uint32_t, kWidth>> wide_source_;  // the binary node in each slot
    std::vector<uint64_t> trail_;
    std::vector<uint8_t> depth_;
    std::vector<float> share_;
};

// A wide node's slot k as the bounds importance() reads.
PackedLightBounds slot_bounds(const LightTree::WideNode& node, int k);
// importance() and estimate() of all four slots at once (SIMD where the machine has it), as the
// descent uses them; the estimate is zero where the importance is.
void wide_weights(const LightTree::WideNode& node, const Vec3& p, const Vec3& n, float bound[4],
                  float guess[4]);

}  // namespace pathfarm
