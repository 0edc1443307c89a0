// glTF 2.0 import through tinygltf: primitives as meshes, the node hierarchy, perspective cameras.
// Images are decoded through image_io.h (JPEG by libturbojpeg, others by OpenImageIO); one that
// cannot be decoded (e.g. KTX2) costs that texture with a warning.
#include <filesystem>

#include <spdlog/spdlog.h>
#include <tiny_gltf.h>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "common/film/image_io.h"
#include "common/math/transform.h"
#include "common/scene/load/gltf_accessor.h"
#include "common/scene/load/gltf_animation.h"
#include "common/scene/load/gltf_material.h"
#include "common/scene/load/scene_loader.h"

namespace pathfarm {
namespace {

struct ImageLoadContext {
    std::string path;
    std::vector<std::string> warnings;
};

std::string image_name_hint(const tinygltf::Image& image) {
    if (!image.uri.empty() && image.uri.rfind("data:", 0) != 0) return image.uri;
    if (image.mimeType == "image/jpeg") return "embedded.jpg";
    if (image.mimeType == "image/png") return "embedded.png";
    if (image.uri.rfind("data:image/jpeg", 0) == 0) return "embedded.jpg";
    return "embedded.png";
}

bool decode_image(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                  const unsigned char* bytes, int size, void* user) {
    auto* ctx = static_cast<ImageLoadContext*>(user);
    auto decoded = decode_rgba8(bytes, std::size_t(size), image_name_hint(*image));
    if (!decoded) {
        ctx->warnings.push_back(
            fmt::format("{}: image {} \"{}\": not decoded ({}); its texture is ignored", ctx->path,
                        index, image->uri, decoded.error().message));
        image->width = image->height = 0;
        return true;  // the scene still loads
    }
    if (decoded->nonfinite_values > 0)
        ctx->warnings.push_back(fmt::format(
            "{}: image {} \"{}\": {} NaN/Inf values (NaN read as 0, infinities clamped)", ctx->path,
            index, image->uri, decoded->nonfinite_values));
    image->width = decoded->width;
    image->height = decoded->height;
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image->image = std::move(decoded->rgba);
    return true;
}

class GltfImporter {
public:
    GltfImporter(const tinygltf::Model& model, std::string path)
        : gltf_(model), path_(std::move(path)) {}
    Result<SceneModel> run();

private:
    Status import_meshes();
    Status import_primitive(const tinygltf::Primitive& prim, const std::string& name, Mesh& mesh);
    Status import_nodes();
    Status add_node(int gltf_node, int parent, int depth);
    void set_node_transform(const tinygltf::Node& gn, Node& node) const;
    Status import_deforming_attributes(const tinygltf::Primitive& prim, const std::string& name,
                                       Mesh& mesh);

    const tinygltf::Model& gltf_;
    std::string path_;
    SceneModel scene_;
    std::vector<std::vector<int>> mesh_map_;  // glTF mesh -> our meshes (one per primitive)
    int default_material_ = -1;
    std::vector<int> node_map_;  // glTF node -> our node, -1 when not in the scene
};

Status GltfImporter::import_primitive(const tinygltf::Primitive& prim, const std::string& name,
                                      Mesh& mesh) {
    const auto attr = [&](const char* key) {
        const auto it = prim.attributes.find(key);
        return it == prim.attributes.end() ? -1 : it->second;
    };
    std::vector<float> data;
    int comps = 0;
    if (Status s = read_accessor_floats(gltf_, attr("POSITION"), data, comps); !s || comps != 3)
        return make_error(ErrorCode::parse_error, "{}: mesh \"{}\": POSITION: {}", path_, name,
                          s ? "not a VEC3" : s.error().message);
    for (std::size_t i = 0; i + 2 < data.size(); i += 3)
        mesh.positions.emplace_back(data[i], data[i + 1], data[i + 2]);
    if (attr("NORMAL") >= 0) {
        if (Status s = read_accessor_floats(gltf_, attr("NORMAL"), data, comps); !s || comps != 3)
            return make_error(ErrorCode::parse_error, "{}: mesh \"{}\": NORMAL: {}", path_, name,
                              s ? "not a VEC3" : s.error().message);
        for (std::size_t i = 0; i + 2 < data.size(); i += 3)
            mesh.normals.emplace_back(data[i], data[i + 1], data[i + 2]);
    }
    if (attr("TEXCOORD_0") >= 0) {
        if (Status s = read_accessor_floats(gltf_, attr("TEXCOORD_0"), data, comps);
            !s || comps != 2)
            return make_error(ErrorCode::parse_error, "{}: mesh \"{}\": TEXCOORD_0: {}", path_,
                              name, s ? "not a VEC2" : s.error().message);
        for (std::size_t i = 0; i + 1 < data.size(); i += 2)
            mesh.uvs.emplace_back(data[i], data[i + 1]);
    }
    if (attr("TANGENT") >= 0) {
        if (Status s = read_accessor_floats(gltf_, attr("TANGENT"), data, comps); !s || comps != 4)
            return make_error(ErrorCode::parse_error, "{}: mesh \"{}\": TANGENT: {}", path_, name,
                              s ? "not a VEC4" : s.error().message);
        for (std::size_t i = 0; i + 3 < data.size(); i += 4)
            mesh.tangents.emplace_back(data[i], data[i + 1], data[i + 2], data[i + 3]);
    }
    std::vector<uint32_t> idx;
    if (prim.indices >= 0) {
        if (Status s = read_accessor_uints(gltf_, prim.indices, idx); !s)
            return make_error(ErrorCode::parse_error, "{}: mesh \"{}\": indices: {}", path_, name,
                              s.error().message);
    } else {
        idx.resize(mesh.positions.size());
        for (uint32_t i = 0; i < idx.size(); ++i)
            idx[i] = i;
    }
    if (prim.mode == TINYGLTF_MODE_TRIANGLES) {
        mesh.indices = std::move(idx);
        mesh.indices.resize(mesh.indices.size() / 3 * 3);
    } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (std::size_t i = 2; i < idx.size(); ++i)
            mesh.indices.insert(
                mesh.indices.end(),
                i % 2 ? std::initializer_list<uint32_t>{idx[i - 1], idx[i - 2], idx[i]}
                      : std::initializer_list<uint32_t>{idx[i - 2], idx[i - 1], idx[i]});
    } else if (prim.mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        for (std::size_t i = 2; i < idx.size(); ++i)
            mesh.indices.insert(mesh.indices.end(), {idx[0], idx[i - 1], idx[i]});
    }
    return {};
}

Status GltfImporter::import_meshes() {
    mesh_map_.resize(gltf_.meshes.size());
    for (std::size_t mi = 0; mi < gltf_.meshes.size(); ++mi) {
        const tinygltf::Mesh& gm = gltf_.meshes[mi];
        for (std::size_t pi = 0; pi < gm.primitives.size(); ++pi) {
            const tinygltf::Primitive& prim = gm.primitives[pi];
            const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
                mode != TINYGLTF_MODE_TRIANGLE_FAN) {
                spdlog::warn("{}: mesh {} \"{}\" primitive {}: points/lines are not rendered",
                             path_, mi, gm.name, pi);
                continue;
            }
            Mesh mesh;
            mesh.name = gm.primitives.size() > 1 ? fmt::format("{}#{}", gm.name, pi) : gm.name;
            if (Status s = import_primitive(prim, mesh.name, mesh); !s) return s;
            if (Status s = import_deforming_attributes(prim, mesh.name, mesh); !s) return s;
            mesh.default_morph_weights.assign(gm.weights.begin(), gm.weights.end());
            if (prim.material >= 0 && prim.material < int(scene_.materials.size())) {
                mesh.material = prim.material;
            } else {
                if (default_material_ < 0) {
                    Material fallback;  // the glTF default material: white, metallic 1, roughness 1
                    fallback.name = "gltf-default";
                    scene_.materials.push_back(std::move(fallback));
                    default_material_ = int(scene_.materials.size()) - 1;
                }
                mesh.material = default_material_;
            }
            if (scene_.materials[mesh.material].normal_texture.valid() && !mesh.has_tangents() &&
                mesh.has_normals())
                compute_tangents(mesh);
            mesh_map_[mi].push_back(int(scene_.meshes.size()));
            scene_.meshes.push_back(std::move(mesh));
        }
    }
    return {};
}

void GltfImporter::set_node_transform(const tinygltf::Node& gn, Node& node) const {
    if (gn.matrix.size() == 16) {
        for (int i = 0; i < 16; ++i)
            glm::value_ptr(node.local)[i] = float(gn.matrix[i]);
        node.has_trs = false;
        return;
    }
    if (gn.translation.size() == 3)
        node.translation = Vec3(gn.translation[0], gn.translation[1], gn.translation[2]);
    if (gn.scale.size() == 3) node.scale = Vec3(gn.scale[0], gn.scale[1], gn.scale[2]);
    if (gn.rotation.size() == 4)  // glTF stores x, y, z, w; glm::quat's constructor takes w first
        node.rotation = glm::normalize(glm::quat(float(gn.rotation[3]), float(gn.rotation[0]),
                                                 float(gn.rotation[1]), float(gn.rotation[2])));
    node.has_trs = true;
    node.local = compose_trs(node.translation, node.rotation, node.scale);
}

Status GltfImporter::import_deforming_attributes(const tinygltf::Primitive& prim,
                                                 const std::string& name, Mesh& mesh) {
    const std::size_t n = mesh.positions.size();
    const auto joints = prim.attributes.find("JOINTS_0");
    const auto weights = prim.attributes.find("WEIGHTS_0");
    if (joints != prim.attributes.end() && weights != prim.attributes.end()) {
        std::vector<uint32_t> j;
        std::vector<float> w;
        int comps = 0;
        Status sj = read_accessor_uints(gltf_, joints->second, j);
        Status sw = read_accessor_floats(gltf_, weights->second, w, comps);
        if (!sj || !sw || j.size() != 4 * n || comps != 4 || w.size() != 4 * n)
            return make_error(ErrorCode::parse_error, "{}: mesh \"{}\": JOINTS_0/WEIGHTS_0: {}",
                              path_, name,
                              !sj   ? sj.error().message
                              : !sw ? sw.error().message
                                    : "not VEC4 per vertex");
        for (std::size_t v = 0; v < n; ++v) {
            mesh.joints.emplace_back(j[4 * v], j[4 * v + 1], j[4 * v + 2], j[4 * v + 3]);
            mesh.weights.emplace_back(w[4 * v], w[4 * v + 1], w[4 * v + 2], w[4 * v + 3]);
        }
    }
    for (const auto& target : prim.targets) {
        MorphTarget mt;
        for (const auto& [attr, out] :
             {std::pair{"POSITION", &mt.positions}, std::pair{"NORMAL", &mt.normals},
              std::pair{"TANGENT", &mt.tangents}}) {
            const auto it = target.find(attr);
            if (it == target.end()) continue;
            std::vector<float> d;
            int comps = 0;
            if (Status st = read_accessor_floats(gltf_, it->second, d, comps);
                !st || comps != 3 || d.size() != 3 * n)
                return make_error(ErrorCode::parse_error, "{}: mesh \"{}\": morph target {}: {}",
                                  path_, name, attr,
                                  st ? "not a VEC3 per vertex" : st.error().message);
            for (std::size_t v = 0; v < n; ++v)
                out->emplace_back(d[3 * v], d[3 * v + 1], d[3 * v + 2]);
        }
        mesh.morph_targets.push_back(std::move(mt));
    }
    return {};
}

Status GltfImporter::add_node(int gltf_node, int parent, int depth) {
    if (gltf_node < 0 || gltf_node >= int(gltf_.nodes.size()))
        return make_error(ErrorCode::parse_error, "{}: node {} out of range", path_, gltf_node);
    if (depth > 256)
        return make_error(ErrorCode::parse_error, "{}: node hierarchy deeper than 256 (a cycle?)",
                          path_);
    const tinygltf::Node& gn = gltf_.nodes[gltf_node];
    Node node;
    node.name = gn.name;
    node.parent = parent;
    set_node_transform(gn, node);
    node.source_index = gltf_node;
    node.skin = gn.skin >= 0 && gn.skin < int(gltf_.skins.size()) ? gn.skin : -1;
    if (gn.mesh >= 0 && gn.mesh < int(mesh_map_.size())) {
        node.meshes = mesh_map_[gn.mesh];
        const auto& defaults = gltf_.meshes[gn.mesh].weights;
        const auto& weights = gn.weights.empty() ? defaults : gn.weights;
        node.morph_weights.assign(weights.begin(), weights.end());
    }
    if (gn.camera >= 0 && gn.camera < int(gltf_.cameras.size())) {
        const tinygltf::Camera& gc = gltf_.cameras[gn.camera];
        Camera cam;
        cam.name = gc.name.empty() ? gn.name : gc.name;
        if (gc.type == "perspective" && gc.perspective.yfov > 0.0)
            cam.yfov_radians = float(gc.perspective.yfov);
        else
            spdlog::warn("{}: camera {} is not perspective; rendered as a 45 degree pinhole", path_,
                         gn.camera);
        scene_.cameras.push_back(cam);
        node.camera = int(scene_.cameras.size()) - 1;
    }
    scene_.nodes.push_back(std::move(node));
    const int self = int(scene_.nodes.size()) - 1;
    for (int child : gn.children)
        if (Status s = add_node(child, self, depth + 1); !s) return s;
    return {};
}

Status GltfImporter::import_nodes() {
    std::vector<int> roots;
    const int scene_index = gltf_.defaultScene >= 0 ? gltf_.defaultScene : 0;
    if (scene_index < int(gltf_.scenes.size())) {
        roots = gltf_.scenes[scene_index].nodes;
    } else {  // no scenes: every node that is nobody's child is a root
        std::vector<bool> is_child(gltf_.nodes.size(), false);
        for (const auto& n : gltf_.nodes)
            for (int c : n.children)
                if (c >= 0 && c < int(is_child.size())) is_child[c] = true;
        for (std::size_t i = 0; i < gltf_.nodes.size(); ++i)
            if (!is_child[i]) roots.push_back(int(i));
    }
    for (int r : roots)
        if (Status s = add_node(r, -1, 0); !s) return s;
    return {};
}

Result<SceneModel> GltfImporter::run() {
    scene_.name = path_;
    import_images_and_textures(gltf_, path_, scene_);
    import_materials(gltf_, path_, scene_);
    if (Status s = import_meshes(); !s) return s.error();
    if (Status s = import_nodes(); !s) return s.error();
    node_map_.assign(gltf_.nodes.size(), -1);
    for (std::size_t i = 0; i < scene_.nodes.size(); ++i)
        node_map_[scene_.nodes[i].source_index] = int(i);
    if (Status s = import_skins(gltf_, path_, node_map_, scene_); !s) return s.error();
    if (Status s = import_animations(gltf_, path_, node_map_, scene_); !s) return s.error();
    flatten_nodes(scene_);
    return std::move(scene_);
}

std::string first_line(const std::string& s) {
    std::string line = s.substr(0, s.find('\n'));
    return line.empty() ? "unknown error" : line;
}

}  // namespace

Result<SceneModel> load_gltf(const std::string& path) {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    ImageLoadContext ctx{path, {}};
    loader.SetImageLoader(&decode_image, &ctx);
    std::string err, warn;
    const bool binary = std::filesystem::path(path).extension() == ".glb";
    bool ok = false;
    try {
        ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                    : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    } catch (const std::exception& e) {  // nlohmann::json inside tinygltf may throw
        return make_error(ErrorCode::parse_error, "{}: {}", path, e.what());
    }
    for (const std::string& w : ctx.warnings)
        spdlog::warn("{}", w);
    if (!ok) return make_error(ErrorCode::parse_error, "{}: {}", path, first_line(err));
    if (!warn.empty()) spdlog::warn("{}: {}", path, first_line(warn));
    return GltfImporter(model, path).run();
}

}  // namespace pathfarm
