// Linear blend skinning and morph targets, parallel over vertex blocks with TBB.
#include "coordinator/animation/skinning.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pathfarm::coord {
namespace {

constexpr std::size_t kVertexGrain = 2048;

void apply_morphs(const Mesh& base, const std::vector<float>& weights, Mesh& out, std::size_t v0,
                  std::size_t v1) {
    for (std::size_t t = 0; t < base.morph_targets.size() && t < weights.size(); ++t) {
        const float w = weights[t];
        if (w == 0.0f) continue;
        const MorphTarget& mt = base.morph_targets[t];
        for (std::size_t v = v0; v < v1; ++v) {
            if (!mt.positions.empty()) out.positions[v] += w * mt.positions[v];
            if (!mt.normals.empty() && out.has_normals()) out.normals[v] += w * mt.normals[v];
            if (!mt.tangents.empty() && out.has_tangents())
                out.tangents[v] += Vec4(w * mt.tangents[v], 0.0f);
        }
    }
}

Mat4 skin_matrix(const Mesh& mesh, std::size_t v, const std::vector<Mat4>& joint_matrices,
                 const Mat4& fallback) {
    const Vec4 w = mesh.weights[v];
    const float sum = w.x + w.y + w.z + w.w;
    if (!(sum > 0.0f)) return fallback;
    Mat4 m(0.0f);
    for (int i = 0; i < 4; ++i) {
        const uint16_t j = mesh.joints[v][i];
        if (w[i] != 0.0f && j < joint_matrices.size()) m += (w[i] / sum) * joint_matrices[j];
    }
    return m;
}

void skin_vertices(Mesh& out, const Mesh& base, const std::vector<Mat4>& joint_matrices,
                   const Mat4& fallback, std::size_t v0, std::size_t v1) {
    for (std::size_t v = v0; v < v1; ++v) {
        const Mat4 m = skin_matrix(base, v, joint_matrices, fallback);
        out.positions[v] = Vec3(m * Vec4(out.positions[v], 1.0f));
        if (out.has_normals() || out.has_tangents()) {
            const Mat3 m3(m);
            if (out.has_normals())
                out.normals[v] = glm::normalize(glm::transpose(glm::inverse(m3)) * out.normals[v]);
            if (out.has_tangents())
                out.tangents[v] =
                    Vec4(glm::normalize(m3 * Vec3(out.tangents[v])), out.tangents[v].w);
        }
    }
}

}  // namespace

std::vector<Mat4> node_world_transforms(const SceneModel& scene) {
    std::vector<Mat4> world(scene.nodes.size());
    for (std::size_t i = 0; i < scene.nodes.size(); ++i) {
        const Node& n = scene.nodes[i];
        world[i] = n.parent >= 0 ? world[n.parent] * n.local : n.local;
    }
    return world;
}

bool is_deforming(const SceneModel& scene, const Instance& instance) {
    const Mesh& mesh = scene.meshes[instance.mesh];
    const Node& node = scene.nodes[instance.node];
    return (node.skin >= 0 && !mesh.joints.empty()) || !mesh.morph_targets.empty();
}

Mesh deform_instance(const SceneModel& scene, const Instance& instance,
                     const std::vector<Mat4>& world) {
    const Mesh& base = scene.meshes[instance.mesh];
    const Node& node = scene.nodes[instance.node];
    Mesh out = base;
    out.morph_targets.clear();
    out.joints.clear();
    out.weights.clear();
    const std::vector<float>& weights =
        node.morph_weights.empty() ? base.default_morph_weights : node.morph_weights;
    std::vector<Mat4> joint_matrices;
    const bool skinned = node.skin >= 0 && !base.joints.empty();
    if (skinned) {
        const Skin& skin = scene.skins[node.skin];
        joint_matrices.resize(skin.joints.size());
        for (std::size_t j = 0; j < skin.joints.size(); ++j)
            joint_matrices[j] = world[skin.joints[j]] * skin.inverse_bind[j];
    }
    const Mat4 fallback = world[instance.node];  // vertices with no weight stay on the node
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, base.positions.size(), kVertexGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          apply_morphs(base, weights, out, r.begin(), r.end());
                          if (skinned)
                              skin_vertices(out, base, joint_matrices, fallback, r.begin(),
                                            r.end());
                      });
    if (!skinned && out.has_normals())
        for (Vec3& n : out.normals)
            n = glm::normalize(n);
    return out;
}

SceneModel pose_scene(const SceneModel& scene) {
    SceneModel posed = scene;
    const std::vector<Mat4> world = node_world_transforms(scene);
    for (Instance& inst : posed.instances) {
        if (!is_deforming(scene, inst)) continue;
        const bool skinned = scene.nodes[inst.node].skin >= 0;
        posed.meshes.push_back(deform_instance(scene, inst, world));
        inst.mesh = int(posed.meshes.size()) - 1;
        if (skinned) inst.transform = Mat4(1.0f);
        inst.dynamic = true;  // as the coordinator's scene graph marks a deforming instance
    }
    return posed;
}

}  // namespace pathfarm::coord
