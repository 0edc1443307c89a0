// Packing a SceneModel into the device layout. The light distribution and the sun/sky numbers
// come from the same LightSampler and SunSky the Embree backend uses, so both backends sample
// the same distributions.
#include "tracer-node/opencl/device_scene.h"

#include <algorithm>
#include <cstring>
#include <type_traits>

#include "common/base/hash.h"
#include "common/math/transform.h"
#include "common/render/light_sampler.h"
#include "common/sampling/rng.h"

namespace pathfarm::tracer {
namespace {

static_assert(sizeof(PfBvhNode) == sizeof(BvhNode), "PfBvhNode mirrors BvhNode");
// The kernels' copies of the C++ enums (device_types.h).
static_assert(PF_STRATEGY_MIS == int(LightStrategy::mis) &&
                  PF_STRATEGY_LIGHT_ONLY == int(LightStrategy::light_only) &&
                  PF_STRATEGY_BSDF_ONLY == int(LightStrategy::bsdf_only),
              "LightStrategy");
static_assert(PF_MAX_LIGHT_CANDIDATES == kMaxLightCandidates && PF_R2_X == kCandidateStepX &&
                  PF_R2_Y == kCandidateStepY,
              "resampled light selection's constants");
static_assert(PF_FEATURE_EMITTERS == kFeatureEmitters &&
                  PF_FEATURE_ENVIRONMENT == kFeatureEnvironment &&
                  PF_FEATURE_TRANSMISSION == kFeatureTransmission,
              "SceneFeature");
static_assert(PF_ALPHA_OPAQUE == unsigned(AlphaMode::opaque) &&
                  PF_ALPHA_MASK == unsigned(AlphaMode::mask) &&
                  PF_ALPHA_BLEND == unsigned(AlphaMode::blend) && kAlphaModeCount == 3,
              "AlphaMode");
static_assert(PF_FILTER_NEAREST == unsigned(FilterMode::nearest) &&
                  PF_FILTER_LINEAR == unsigned(FilterMode::linear) && kFilterModeCount == 2,
              "FilterMode");
static_assert(PF_WRAP_REPEAT == unsigned(WrapMode::repeat) &&
                  PF_WRAP_CLAMP_TO_EDGE == unsigned(WrapMode::clamp_to_edge) &&
                  PF_WRAP_MIRRORED_REPEAT == unsigned(WrapMode::mirrored_repeat) &&
                  kWrapModeCount == 3,
              "WrapMode");
static_assert(sizeof(PfLightNode) == sizeof(LightTree::WideNode) &&
                  std::is_trivially_copyable_v<LightTree::WideNode> &&
                  PF_LIGHT_TWO_SIDED == kPackedTwoSided && PF_LIGHT_LEAF == LightTree::kLeaf &&
                  PF_LIGHT_PAIR == LightTree::kPair &&
                  PF_LIGHT_DISTANT_SIN2 == LightTree::kDistantSin2 &&
                  PF_LIGHT_DISTANT_COS == LightTree::kDistantCos,
              "PfLightNode mirrors LightTree::WideNode");
static_assert(offsetof(PfLightNode, power) == offsetof(LightTree::WideNode, power) &&
                  offsetof(PfLightNode, mean_normal) ==
                      offsetof(LightTree::WideNode, mean_normal) &&
                  offsetof(PfLightNode, diffuse_share) ==
                      offsetof(LightTree::WideNode, diffuse_share) &&
                  offsetof(PfLightNode, flags) == offsetof(LightTree::WideNode, flags) &&
                  offsetof(PfLightNode, child) == offsetof(LightTree::WideNode, child),
              "PfLightNode's fields where LightTree::WideNode has them");
static_assert(sizeof(PfInstance) == 36 * 4 && sizeof(PfMesh) == 8 * 4 &&
                  sizeof(PfMaterial) == 51 * 4 && sizeof(PfTexture) == 7 * 4 &&
                  sizeof(PfLight) == 20 * 4 && sizeof(PfLightNode) == 64 * 4 &&
                  sizeof(PfSceneGlobals) == (42 + 256 + 1024) * 4 &&
                  sizeof(PfFrameParams) == 28 * 4,
              "device structs are packed 4-byte fields (device_types.h)");

void store_rows(const Mat4& m, float out[12]) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            out[4 * r + c] = m[c][r];
}

void store3(const Vec3& v, float out[3]) {
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
}

uint64_t mesh_geometry_hash(const Mesh& mesh) {
    uint64_t h = fnv1a64(reinterpret_cast<const unsigned char*>(mesh.positions.data()),
                         mesh.positions.size() * sizeof(Vec3));
    return fnv1a64(reinterpret_cast<const unsigned char*>(mesh.indices.data()),
                   mesh.indices.size() * sizeof(uint32_t), h);
}

PfInstance pack_instance(const Instance& inst) {
    PfInstance out{};
    store_rows(inst.transform, out.object_to_world);
    store_rows(glm::inverse(inst.transform), out.world_to_object);
    const Mat3 nm = normal_matrix(inst.transform);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            out.normal_matrix[3 * r + c] = nm[c][r];
    out.handedness = glm::determinant(Mat3(inst.transform)) < 0.0f ? -1.0f : 1.0f;
    out.mesh = uint32_t(inst.mesh);
    out.first_light = -1;
    return out;
}

// UvTransform::apply as the affine map the kernels apply.
void store_uv_transform(const UvTransform& t, float out[6]) {
    const float c = std::cos(t.rotation), s = std::sin(t.rotation);
    const float m[6] = {c * t.scale.x,  s * t.scale.y, t.offset.x,
                        -s * t.scale.x, c * t.scale.y, t.offset.y};
    std::copy(m, m + 6, out);
}

PfMaterial pack_material(const Material& m) {
    PfMaterial out{};
    for (int c = 0; c < 4; ++c)
        out.base_color[c] = m.base_color_factor[c];
    store3(m.emission(), out.emission);
    out.metallic = m.metallic_factor;
    out.roughness = m.roughness_factor;
    out.transmission = m.transmission_factor;
    out.ior = m.ior;
    out.specular = m.specular_factor;
    store3(m.specular_color_factor, out.specular_color);
    out.normal_scale = m.normal_scale;
    // ShadingScene::absorption_coefficient
    Rgb sigma(0.0f);
    if (std::isfinite(m.attenuation_distance) && m.attenuation_distance > 0.0f)
        sigma = -glm::log(glm::clamp(m.attenuation_color, Rgb(1e-6f), Rgb(1.0f))) /
                m.attenuation_distance;
    store3(sigma, out.sigma_a);
    out.base_color_texture = m.base_color_texture.texture;
    out.metallic_roughness_texture = m.metallic_roughness_texture.texture;
    out.normal_texture = m.normal_texture.texture;
    out.emissive_texture = m.emissive_texture.texture;
    out.double_sided = m.double_sided ? 1u : 0u;
    out.emissive = m.is_emissive() ? 1u : 0u;
    out.alpha_mode = uint32_t(m.alpha_mode);
    out.alpha_cutoff = m.alpha_cutoff;
    store_uv_transform(m.base_color_texture.transform, out.base_color_uv);
    store_uv_transform(m.metallic_roughness_texture.transform, out.metallic_roughness_uv);
    store_uv_transform(m.normal_texture.transform, out.normal_uv);
    store_uv_transform(m.emissive_texture.transform, out.emissive_uv);
    return out;
}

Bounds3f instance_bounds(const BvhNode& root, const Mat4& transform) {
    Bounds3f b;
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 p((corner & 1) ? root.upper[0] : root.lower[0],
                     (corner & 2) ? root.upper[1] : root.lower[1],
                     (corner & 4) ? root.upper[2] : root.lower[2]);
        b.extend(transform_point(transform, p));
    }
    // The transformed corners are rounded to float: pad by a few ulps so that the box stays
    // conservative (rounding to nearest may shrink it by half an ulp).
    const Vec3 pad = 4e-7f * glm::max(glm::abs(b.lower), glm::abs(b.upper)) + Vec3(1e-30f);
    b.lower -= pad;
    b.upper += pad;
    return b;
}

// The wide nodes as they are (the same layout: static_assert above) and the root's bounds.
void pack_light_tree(const LightTree& tree, PackedScene& out) {
    out.light_nodes.resize(tree.wide_nodes().size());
    if (!out.light_nodes.empty())
        std::memcpy(out.light_nodes.data(), tree.wide_nodes().data(),
                    out.light_nodes.size() * sizeof(PfLightNode));
    PfSceneGlobals& g = out.globals;
    g.light_tree = tree.empty() ? 0u : 1u;
    if (tree.empty()) return;
    const PackedLightBounds& root = tree.root_bounds();
    std::copy(root.center, root.center + 3, g.light_root_center);
    g.light_root_radius2 = root.radius2;
    g.light_root_cos_theta_o = root.cos_theta_o;
    g.light_root_leaf = tree.is_leaf(0) ? 1u : 0u;
}

}  // namespace

void pack_lights(const SceneModel& scene, const std::vector<bool>& excluded,
                 LightSelection selection, PackedScene& out, LightTopologyCache* topology) {
    const ShadingScene shading(scene);
    const LightSampler lights(shading, excluded, selection, topology);
    out.lights.clear();
    out.light_nodes.clear();
    out.light_guide = lights.cdf_guide();
    const LightTree& tree = lights.tree();
    out.light_selection = lights.selection();
    out.light_choice = lights.choice();
    out.features = scene_features(shading, lights);
    const auto& cdf = lights.cdf();
    for (std::size_t k = 0; k < lights.triangles().size(); ++k) {
        const auto& t = lights.triangles()[k];
        PfLight l{};
        store3(t.p0, l.p0);
        store3(t.e1, l.e1);
        store3(t.e2, l.e2);
        store3(t.n, l.n);
        l.area = t.area;
        l.cdf = cdf[k];
        l.instance = t.instance;
        l.prim = t.prim;
        l.material = t.material;
        if (!tree.empty()) {
            l.trail_lo = uint32_t(tree.trails()[k]);
            l.trail_hi = uint32_t(tree.trails()[k] >> 32);
            l.tree_share = tree.leaf_shares()[k];
        }
        out.lights.push_back(l);
    }
    pack_light_tree(tree, out);
    for (uint32_t i = 0; i < out.instances.size(); ++i)
        out.instances[i].first_light = int32_t(lights.first_light_of(i));
    PfSceneGlobals& g = out.globals;
    g.light_count = uint32_t(out.lights.size());
    g.p_environment = lights.environment_probability();
    g.has_environment = lights.has_environment() ? 1u : 0u;
    if (const SunSky* sky = lights.sun_sky()) {
        const SunSkyParams p = sky->params();
        store3(p.sun_dir, g.sun_dir);
        g.sun_cos_max = p.sun_cos_max;
        store3(p.sun_radiance, g.sun_radiance);
        g.sky_scale = p.sky_scale;
        g.p_sun = p.p_sun;
        std::copy(p.perez_y, p.perez_y + 5, g.perez_y);
        std::copy(p.perez_x, p.perez_x + 5, g.perez_x);
        std::copy(p.perez_yy, p.perez_yy + 5, g.perez_yy);
        g.zenith_y = p.zenith_y;
        g.zenith_x = p.zenith_x;
        g.zenith_yy = p.zenith_yy;
        g.theta_sun = p.theta_sun;
        g.perez_zenith_y = p.perez_zenith_y;
        g.perez_zenith_x = p.perez_zenith_x;
        g.perez_zenith_yy = p.perez_zenith_yy;
    }
}

const Bvh& LocalBvhCache::get(std::size_t mesh_index, const Mesh& mesh) {
    const uint64_t content = mesh_geometry_hash(mesh);
    auto it = entries_.find(mesh_index);
    if (it == entries_.end() || it->second.content != content) {
        Entry e{content, build_bvh(mesh.positions, mesh.indices)};
        it = entries_.insert_or_assign(mesh_index, std::move(e)).first;
    }
    return it->second.bvh;
}

bool is_traversable_bvh(const std::vector<BvhNode>& nodes, const std::vector<uint32_t>& prims,
                        std::size_t triangle_count) {
    if (nodes.empty()) return triangle_count == 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const BvhNode& n = nodes[i];
        if (n.count == 0) {
            if (i + 1 >= nodes.size() || n.first <= i + 1 || n.first >= nodes.size()) return false;
        } else if (std::size_t(n.first) + n.count > prims.size()) {
            return false;
        }
    }
    return std::all_of(prims.begin(), prims.end(), [&](uint32_t p) { return p < triangle_count; });
}

namespace {

uint32_t mesh_flags(const SceneModel& scene, const Mesh& mesh) {
    const std::size_t nv = mesh.positions.size();
    return (mesh.normals.size() == nv && nv > 0 ? PF_MESH_NORMALS : 0u) |
           (mesh.uvs.size() == nv && nv > 0 ? PF_MESH_UVS : 0u) |
           (mesh.tangents.size() == nv && nv > 0 ? PF_MESH_TANGENTS : 0u) |
           (scene.materials[std::size_t(mesh.material)].alpha_tested() ? PF_MESH_ALPHA_TESTED : 0u);
}

void append_nodes(const std::vector<BvhNode>& nodes, std::vector<PfBvhNode>& out) {
    for (const BvhNode& n : nodes) {
        PfBvhNode pn;
        std::memcpy(&pn, &n, sizeof pn);
        out.push_back(pn);
    }
}

// Mesh m's vertices, indices and BVH (the coordinator's if it is safe to traverse, else the
// tracer's own) appended to the arrays.
void pack_mesh(const SceneModel& scene, std::size_t m, const std::vector<MeshBvhView>& bvhs,
               LocalBvhCache& cache, PackedScene& out) {
    const Mesh& mesh = scene.meshes[m];
    PfMesh pm{};
    pm.first_index = uint32_t(out.indices.size());
    pm.triangle_count = uint32_t(mesh.triangle_count());
    pm.first_vertex = uint32_t(out.positions.size() / 3);
    pm.material = mesh.material;
    pm.flags = mesh_flags(scene, mesh);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3& p = mesh.positions[v];
        const Vec3 n = (pm.flags & PF_MESH_NORMALS) ? mesh.normals[v] : Vec3(0.0f);
        const Vec2 uv = (pm.flags & PF_MESH_UVS) ? mesh.uvs[v] : Vec2(0.0f);
        const Vec4 t = (pm.flags & PF_MESH_TANGENTS) ? mesh.tangents[v] : Vec4(0.0f);
        out.positions.insert(out.positions.end(), {p.x, p.y, p.z});
        out.normals.insert(out.normals.end(), {n.x, n.y, n.z});
        out.uvs.insert(out.uvs.end(), {uv.x, uv.y});
        out.tangents.insert(out.tangents.end(), {t.x, t.y, t.z, t.w});
    }
    out.indices.insert(out.indices.end(), mesh.indices.begin(),
                       mesh.indices.begin() + std::ptrdiff_t(3 * mesh.triangle_count()));
    const std::vector<BvhNode>* nodes = nullptr;
    const std::vector<uint32_t>* prims = nullptr;
    if (m < bvhs.size() && bvhs[m].nodes && bvhs[m].prim_indices &&
        is_traversable_bvh(*bvhs[m].nodes, *bvhs[m].prim_indices, mesh.triangle_count())) {
        nodes = bvhs[m].nodes;
        prims = bvhs[m].prim_indices;
    } else {
        const Bvh& own = cache.get(m, mesh);
        nodes = &own.nodes;
        prims = &own.prim_indices;
        ++out.meshes_with_own_bvh;
    }
    pm.first_node = uint32_t(out.nodes.size());
    pm.node_count = pm.triangle_count > 0 ? uint32_t(nodes->size()) : 0u;
    pm.first_prim = uint32_t(out.prims.size());
    append_nodes(*nodes, out.nodes);
    out.prims.insert(out.prims.end(), prims->begin(), prims->end());
    out.meshes.push_back(pm);
}

// The instances and the top-level BVH over their world boxes (meshes packed first).
void pack_instances(const SceneModel& scene, PackedScene& out) {
    std::vector<Bounds3f> boxes;
    std::vector<uint32_t> box_instance;
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        out.instances.push_back(pack_instance(inst));
        const PfMesh& pm = out.meshes[std::size_t(inst.mesh)];
        if (pm.node_count == 0) continue;
        BvhNode root;
        std::memcpy(&root, &out.nodes[pm.first_node], sizeof root);
        const Bounds3f b = instance_bounds(root, inst.transform);
        if (b.empty() || !is_finite(b.lower) || !is_finite(b.upper)) continue;
        boxes.push_back(b);
        box_instance.push_back(i);
    }
    if (!boxes.empty()) {
        const Bvh top = build_bvh(boxes);
        append_nodes(top.nodes, out.top_nodes);
        for (uint32_t p : top.prim_indices)
            out.top_prims.push_back(box_instance[p]);
    }
    out.globals.instance_count = uint32_t(out.top_prims.size());
}

void pack_textures(const SceneModel& scene, const TextureMips* mips, PackedScene& out) {
    std::vector<uint32_t> image_first(scene.images.size(), 0);
    std::vector<uint32_t> image_levels(scene.images.size(), 0);
    for (std::size_t i = 0; i < scene.images.size(); ++i) {
        image_first[i] = uint32_t(out.texels.size() / 4);
        out.texels.insert(out.texels.end(), scene.images[i].rgba.begin(),
                          scene.images[i].rgba.end());
        if (!mips) continue;
        const std::vector<Image>& levels = mips->levels(int(i));
        image_levels[i] = uint32_t(levels.size());
        for (const Image& level : levels)
            out.texels.insert(out.texels.end(), level.rgba.begin(), level.rgba.end());
    }
    for (const Texture& t : scene.textures) {
        PfTexture pt{};
        const Image* im = t.image >= 0 && std::size_t(t.image) < scene.images.size()
                              ? &scene.images[std::size_t(t.image)]
                              : nullptr;
        if (im && im->rgba.size() == std::size_t(im->width) * std::size_t(im->height) * 4) {
            pt.first_texel = image_first[std::size_t(t.image)];
            pt.width = im->width;
            pt.height = im->height;
            pt.levels = image_levels[std::size_t(t.image)];
        }
        pt.filter = t.sampler.filter == FilterMode::nearest ? PF_FILTER_NEAREST : PF_FILTER_LINEAR;
        pt.wrap_s = uint32_t(t.sampler.wrap_s);
        pt.wrap_t = uint32_t(t.sampler.wrap_t);
        out.textures.push_back(pt);
    }
}

}  // namespace

PackedScene pack_scene(const SceneModel& scene, const std::vector<MeshBvhView>& bvhs,
                       LocalBvhCache& cache, const TextureMips* mips) {
    PackedScene out;
    for (std::size_t m = 0; m < scene.meshes.size(); ++m)
        pack_mesh(scene, m, bvhs, cache, out);
    pack_instances(scene, out);
    // The tables the kernels read instead of computing (docs/opencl.md): sRGB and Sobol.
    for (int i = 0; i < 256; ++i)
        out.globals.srgb_to_linear[i] = srgb_to_linear(float(i) / 255.0f);
    for (int b = 0; b < 4; ++b)
        for (int v = 0; v < 256; ++v)
            out.globals.sobol_dim1[256 * b + v] = detail::kSobolDim1.table[b][v];
    for (const Material& m : scene.materials)
        out.materials.push_back(pack_material(m));
    pack_textures(scene, mips, out);
    pack_lights(scene, {}, LightSelection::power, out);
    return out;
}

}  // namespace pathfarm::tracer
