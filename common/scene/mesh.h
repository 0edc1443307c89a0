// Triangle meshes in object space. Optional attributes are either empty or one per vertex.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/gtc/type_precision.hpp>

#include "common/math/types.h"

namespace pathfarm {

// Per-vertex offsets of one morph target (glTF: each attribute is a delta). Empty arrays mean
// the target does not change that attribute.
struct MorphTarget {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;
    std::vector<Vec3> tangents;
};

struct Mesh {
    std::string name;
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;      // empty: flat shading (glTF requires flat normals then)
    std::vector<Vec2> uvs;          // TEXCOORD_0
    std::vector<Vec4> tangents;     // xyz tangent, w = bitangent sign (glTF)
    std::vector<uint32_t> indices;  // three per triangle, counter-clockwise = front face
    int material = 0;
    // Skinning (JOINTS_0 / WEIGHTS_0): joint indices into the node's skin, one set per vertex.
    std::vector<glm::u16vec4> joints;
    std::vector<Vec4> weights;
    std::vector<MorphTarget> morph_targets;
    std::vector<float> default_morph_weights;  // glTF mesh.weights

    std::size_t triangle_count() const { return indices.size() / 3; }
    bool has_normals() const { return !normals.empty(); }
    bool has_uvs() const { return !uvs.empty(); }
    bool has_tangents() const { return !tangents.empty(); }
};

// Fills per-vertex tangents from UVs and normals (accumulated per triangle, Gram–Schmidt
// orthogonalised) for meshes that have a normal map but no TANGENT attribute.
void compute_tangents(Mesh& mesh);

// Area-weighted vertex normals, for built-in meshes that want smooth shading.
void compute_smooth_normals(Mesh& mesh);

}  // namespace pathfarm
