// Procedural meshes for built-in scenes and tests. All are counter-clockwise seen from outside.
#pragma once

#include "common/scene/mesh.h"

namespace pathfarm {

// A quad centred at c spanned by half-axes u and v; its front face points along cross(u, v).
// UVs run (0,0) at c - u - v to (1,1) at c + u + v.
Mesh make_quad(const Vec3& c, const Vec3& u, const Vec3& v, int material);
// The cube [-0.5, 0.5]^3 with outward faces, flat shaded.
Mesh make_unit_cube(int material);
// A UV sphere of radius r at the origin with smooth normals, UVs and tangents.
Mesh make_sphere(float radius, int rings, int segments, int material);
// An open-ended cylinder of radius r along +Y from y = 0 to y = height, capped, smooth sides.
Mesh make_cylinder(float radius, float height, int segments, int material);

// The same mesh seen from inside: winding and normals reversed (an enclosure's front faces
// point inward).
Mesh turned_inside_out(Mesh m);

// Appends b's triangles to a (both must have the same attribute set).
void append_mesh(Mesh& a, const Mesh& b);

}  // namespace pathfarm
