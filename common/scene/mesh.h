// Triangle meshes in object space. Optional attributes are either empty or one per vertex.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/math/types.h"

namespace pathfarm {

struct Mesh {
    std::string name;
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;      // empty: flat shading (glTF requires flat normals then)
    std::vector<Vec2> uvs;          // TEXCOORD_0
    std::vector<Vec4> tangents;     // xyz tangent, w = bitangent sign (glTF)
    std::vector<uint32_t> indices;  // three per triangle, counter-clockwise = front face
    int material = 0;

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
