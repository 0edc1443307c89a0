// Plain structs shared between the C++ host code and the OpenCL C kernels: the build prepends
// this header to the kernel source, so both sides read one definition. Every field is 4 bytes
// wide (no vector types), so C++ and OpenCL C lay the structs out identically; the host
// static_asserts the sizes.
#ifndef PATHFARM_OPENCL_DEVICE_TYPES_H
#define PATHFARM_OPENCL_DEVICE_TYPES_H

#ifdef __OPENCL_C_VERSION__
typedef uint pf_uint;
typedef int pf_int;
typedef uchar pf_uchar;
#else
#include <cstdint>
typedef uint32_t pf_uint;
typedef int32_t pf_int;
typedef uint8_t pf_uchar;
#endif

#define PF_MESH_NORMALS 1u
#define PF_MESH_UVS 2u
#define PF_MESH_TANGENTS 4u
#define PF_MESH_ALPHA_TESTED 8u  // its material's alpha may discard hits (Material::alpha_tested)

// LightStrategy, in the same order as common/render/path_tracer.h.
#define PF_STRATEGY_MIS 0
#define PF_STRATEGY_LIGHT_ONLY 1
#define PF_STRATEGY_BSDF_ONLY 2
#define PF_MAX_LIGHT_CANDIDATES 16  // kMaxLightCandidates
// The R2 sequence's step that shifts each RIS candidate's point (direct_light.cpp).
#define PF_R2_X 0.75487766624669276f
#define PF_R2_Y 0.56984029099805327f

// SceneFeature bits, as common/render/path_tracer.h.
#define PF_FEATURE_EMITTERS 1u
#define PF_FEATURE_ENVIRONMENT 2u
#define PF_FEATURE_TRANSMISSION 4u

// AlphaMode (common/scene/material.h), FilterMode and WrapMode (common/scene/texture.h).
#define PF_ALPHA_OPAQUE 0u
#define PF_ALPHA_MASK 1u
#define PF_ALPHA_BLEND 2u
#define PF_FILTER_NEAREST 0u
#define PF_FILTER_LINEAR 1u
#define PF_WRAP_REPEAT 0u
#define PF_WRAP_CLAMP_TO_EDGE 1u
#define PF_WRAP_MIRRORED_REPEAT 2u
// (device_scene.cpp static_asserts each mirrored value against its C++ enum.)

// Same layout as pathfarm::BvhNode (common/scene/bvh_node.h).
typedef struct {
    float lower[3];
    pf_uint first;  // interior: right child; leaf: first entry of the primitive index array
    float upper[3];
    pf_uint count;  // 0 for interior nodes
} PfBvhNode;

// 3x4 matrices are stored by rows: m[4 * r + c], column 3 the translation.
typedef struct {
    float object_to_world[12];
    float world_to_object[12];
    float normal_matrix[9];  // rows of the inverse transpose of the upper 3x3
    float handedness;        // sign of the transform's determinant
    pf_uint mesh;
    pf_int
        first_light;  // index of the instance's first emissive triangle in the light array, or -1
} PfInstance;

typedef struct {
    pf_uint first_index;  // into the index array (3 per triangle; values are mesh-local)
    pf_uint triangle_count;
    pf_uint first_vertex;  // into the vertex attribute arrays
    pf_uint first_node;    // root of the mesh's BVH in the node array
    pf_uint first_prim;    // into the BVH primitive index array
    pf_uint flags;         // PF_MESH_*
    pf_int material;
    pf_uint node_count;
} PfMesh;

typedef struct {
    float base_color[4];
    float emission[3];  // emissive factor * strength
    float metallic;
    float roughness;
    float transmission;
    float ior;
    float specular;
    float specular_color[3];
    float normal_scale;
    float sigma_a[3];  // Beer absorption per metre
    pf_int base_color_texture;
    pf_int metallic_roughness_texture;
    pf_int normal_texture;
    pf_int emissive_texture;
    pf_uint double_sided;
    pf_uint emissive;
    pf_uint alpha_mode;  // AlphaMode: 0 opaque, 1 mask, 2 blend
    float alpha_cutoff;
    // KHR_texture_transform of each texture use as a 2x3 affine map, row-major:
    // uv' = (m0 u + m1 v + m2, m3 u + m4 v + m5).
    float base_color_uv[6];
    float metallic_roughness_uv[6];
    float normal_uv[6];
    float emissive_uv[6];
} PfMaterial;

// A texture with its image resolved; width 0 means the image is missing (samples are white).
typedef struct {
    pf_uint first_texel;  // into the RGBA8 texel array, in texels
    pf_int width;
    pf_int height;
    pf_uint filter;  // 0 nearest, 1 linear (FilterMode)
    pf_uint wrap_s;  // WrapMode: 0 repeat, 1 clamp to edge, 2 mirrored repeat
    pf_uint wrap_t;
    // Mip levels past 0 stored after level 0 (texture_mips.h): level l+1 halves level l's
    // sizes (floored, at least 1) and follows it in the texel array; 0 without mips.
    pf_uint levels;
} PfTexture;

// An emissive triangle of LightSampler, in world space.
typedef struct {
    float p0[3];
    float e1[3];
    float e2[3];
    float n[3];
    float area;
    float cdf;  // normalised cumulative power up to and including this triangle
    pf_uint instance;
    pf_uint prim;
    pf_int material;
    // Its path from the light tree's wide root (LightTree::trails): two bits per depth, the
    // slot taken; bits 0-31 in trail_lo.
    pf_uint trail_lo;
    pf_uint trail_hi;
    float tree_share;  // LightTree::leaf_shares: its probability once its leaf is chosen
} PfLight;

// A wide light tree node (LightTree::WideNode): four slots' bounds side by side, then each
// slot's flags and child (a wide node, or a leaf's first emitter). Unused slots: power zero.
typedef struct {
    float center[3][4];
    float radius2[4];
    float axis[3][4];
    float cos_theta_o[4];
    float sin_theta_o[4];
    float power[4];
    float mean_normal[3][4];  // what the estimate reads (light_bounds.h)
    float diffuse_share[4];
    pf_uint flags[4];  // PF_LIGHT_TWO_SIDED, PF_LIGHT_LEAF, PF_LIGHT_PAIR
    pf_uint child[4];
} PfLightNode;

#define PF_LIGHT_TWO_SIDED 1u  // kPackedTwoSided
#define PF_LIGHT_LEAF 2u       // LightTree::kLeaf
#define PF_LIGHT_PAIR 4u       // LightTree::kPair
// LightTree's distant-node switch to choosing by power.
#define PF_LIGHT_DISTANT_SIN2 0.02f
#define PF_LIGHT_DISTANT_COS 0.0f

// Scene-wide values: the sun/sky (SunSkyParams) and the light selection.
typedef struct {
    float sun_dir[3];
    float sun_cos_max;
    float sun_radiance[3];
    float sky_scale;
    float p_sun;
    float perez_y[5];
    float perez_x[5];
    float perez_yy[5];
    float zenith_y;
    float zenith_x;
    float zenith_yy;
    float theta_sun;
    float perez_zenith_y;  // each Perez function at the zenith (sky_radiance divides by them)
    float perez_zenith_x;
    float perez_zenith_yy;
    float p_environment;  // probability of sampling the sun/sky rather than a triangle
    pf_uint has_environment;
    pf_uint light_count;
    pf_uint light_tree;  // nonzero: emitters are chosen through light_nodes (LightSelection)
    // The whole tree's bounds (LightTree::root_bounds), for the distant switch at the root;
    // light_root_leaf: the binary tree is one leaf (no importance to weigh).
    float light_root_center[3];
    float light_root_radius2;
    float light_root_cos_theta_o;
    pf_uint light_root_leaf;
    pf_uint instance_count;
    // sRGB-encoded byte -> linear, the host's table (common/scene/texture.cpp): a pow() per
    // channel per texel took a third of the time on PoCL.
    float srgb_to_linear[256];
    // The sampler's byte tables for the second Sobol dimension (common/sampling/rng.h).
    pf_uint sobol_dim1[4 * 256];
} PfSceneGlobals;

// One kernel launch: rows [y0, y1) of a frame.
typedef struct {
    float camera_to_world[12];
    float tan_half_fov;
    pf_int width;
    pf_int height;
    pf_uint frame;
    pf_uint seed;
    pf_int spp;
    pf_int first_sample;
    pf_int y0;
    pf_int y1;
    pf_int max_depth;
    pf_int strategy;  // PF_STRATEGY_*
    pf_int rr_start_depth;
    float rr_scale;
    pf_int first_hits;        // nonzero: write each pixel's first hit (common/film/first_hits.h)
    pf_int light_candidates;  // IntegratorSettings::light_candidates
    pf_int extra_samples;     // nonzero: the extra_samples argument holds a byte per pixel
} PfFrameParams;

// The scene's device arrays in kernel argument order (after PfFrameParams, before the
// PfSceneGlobals): name and element type. One list that both compilers expand: the kernel's
// parameters and PfScene (kernels/*.cl), the host's PackedScene, its device arrays, their
// uploads and the kernel arguments (device_scene.h, opencl_backend.cpp). An X-macro because C
// and OpenCL C share no other way to write a table of fields once.
#define PF_SCENE_ARRAYS(X)                                              \
    X(positions, float) /* 3 per vertex, all meshes back to back */     \
    X(normals, float)   /* 3 per vertex; zeros where a mesh has none */ \
    X(uvs, float)       /* 2 per vertex */                              \
    X(tangents, float)  /* 4 per vertex */                              \
    X(indices, pf_uint) /* 3 per triangle, mesh-local */                \
    X(meshes, PfMesh)                                                   \
    X(instances, PfInstance)                                            \
    X(nodes, PfBvhNode) /* every mesh's BVH, back to back */            \
    X(prims, pf_uint)                                                   \
    X(top_nodes, PfBvhNode) /* over the instances */                    \
    X(top_prims, pf_uint)                                               \
    X(materials, PfMaterial)                                            \
    X(textures, PfTexture)                                              \
    X(texels, pf_uchar) /* RGBA8, all images back to back */            \
    X(lights, PfLight)                                                  \
    X(light_guide, pf_uint) /* GuidedCdf's guide over lights' cdf */    \
    X(light_nodes, PfLightNode)

#endif  // PATHFARM_OPENCL_DEVICE_TYPES_H
