// Wavefront OBJ + MTL through tinyobjloader (gzip through zlib). One mesh per material;
// MTL parameters are mapped onto the glTF material model (see docs/scene-formats.md).
#include <filesystem>
#include <sstream>
#include <unordered_map>

#include <spdlog/spdlog.h>
#include <tiny_obj_loader.h>

#include "common/film/image_io.h"
#include "common/scene/load/file_read.h"
#include "common/scene/load/scene_loader.h"

namespace pathfarm {
namespace {

struct VertexKey {
    int v, n, t;
    bool operator==(const VertexKey&) const = default;
};
struct VertexKeyHash {
    std::size_t operator()(const VertexKey& k) const {
        return std::hash<uint64_t>()((uint64_t(uint32_t(k.v)) << 32) ^
                                     (uint64_t(uint32_t(k.n)) << 16) ^ uint32_t(k.t));
    }
};

// Phong exponent to GGX roughness via the Beckmann-equivalent alpha = sqrt(2 / (Ns + 2)).
float roughness_from_shininess(float ns) {
    if (ns >= 1000.0f) return 0.0f;  // MTL's "perfect mirror" convention
    return std::sqrt(std::sqrt(2.0f / (std::max(ns, 0.0f) + 2.0f)));
}

class ObjImporter {
public:
    ObjImporter(std::string path)
        : path_(std::move(path)), dir_(std::filesystem::path(path_).parent_path().string()) {}
    Result<SceneModel> run(const std::string& text);

private:
    Material convert_material(const tinyobj::material_t& m);
    TextureRef load_texture(const std::string& name);
    void build_meshes(const tinyobj::attrib_t& attrib, const std::vector<tinyobj::shape_t>& shapes);

    std::string path_, dir_;
    SceneModel scene_;
    std::unordered_map<std::string, int> texture_cache_;
};

TextureRef ObjImporter::load_texture(const std::string& name) {
    if (name.empty()) return {};
    if (const auto it = texture_cache_.find(name); it != texture_cache_.end())
        return {it->second, 0, {}};
    std::string file = name;
    std::replace(file.begin(), file.end(), '\\', '/');
    auto image = read_rgba8((std::filesystem::path(dir_) / file).string());
    int texture = -1;
    if (!image) {
        spdlog::warn("{}: texture \"{}\" not loaded ({}); ignored", path_, name,
                     image.error().message);
    } else {
        if (image->nonfinite_values > 0)
            spdlog::warn(
                "{}: texture \"{}\": {} NaN/Inf values (NaN read as 0, infinities clamped)", path_,
                name, image->nonfinite_values);
        scene_.images.push_back(Image{name, image->width, image->height, std::move(image->rgba)});
        scene_.textures.push_back(Texture{int(scene_.images.size()) - 1, Sampler{}});
        texture = int(scene_.textures.size()) - 1;
    }
    texture_cache_[name] = texture;
    return {texture, 0, {}};
}

Material ObjImporter::convert_material(const tinyobj::material_t& om) {
    Material m;
    m.name = om.name;
    const Rgb kd(om.diffuse[0], om.diffuse[1], om.diffuse[2]);
    const Rgb ks(om.specular[0], om.specular[1], om.specular[2]);
    m.emissive_factor = Rgb(om.emission[0], om.emission[1], om.emission[2]);
    m.base_color_factor = Vec4(kd, 1.0f);
    m.base_color_texture = load_texture(om.diffuse_texname);
    m.normal_texture = load_texture(om.normal_texname);
    m.roughness_factor = roughness_from_shininess(om.shininess);
    m.metallic_factor = 0.0f;
    const bool refractive = om.illum == 4 || om.illum == 6 || om.illum == 7 || om.dissolve < 1.0f;
    if (refractive) {
        m.transmission_factor = 1.0f;
        m.ior = om.ior > 1.0f ? om.ior : 1.0001f;  // Ni 1 marks thin window panes
        m.roughness_factor = 0.0f;
    } else if (max_component(ks) > 0.0f && max_component(ks) >= max_component(kd)) {
        m.metallic_factor = 1.0f;  // a mirror or polished metal: Ks is its colour
        m.base_color_factor = Vec4(ks, 1.0f);
    } else {
        m.specular_factor = std::clamp(max_component(ks), 0.0f, 1.0f);  // 0 is pure Lambert
    }
    return m;
}

void ObjImporter::build_meshes(const tinyobj::attrib_t& attrib,
                               const std::vector<tinyobj::shape_t>& shapes) {
    std::vector<Mesh> meshes(scene_.materials.size());
    std::vector<std::unordered_map<VertexKey, uint32_t, VertexKeyHash>> maps(meshes.size());
    const bool have_normals = !attrib.normals.empty();
    const bool have_uvs = !attrib.texcoords.empty();
    for (const tinyobj::shape_t& shape : shapes) {
        const auto& idx = shape.mesh.indices;
        for (std::size_t f = 0; f < shape.mesh.material_ids.size(); ++f) {
            int mat = shape.mesh.material_ids[f];
            if (mat < 0 || mat >= int(meshes.size()) - 1) mat = int(meshes.size()) - 1;  // default
            Mesh& mesh = meshes[mat];
            for (int k = 0; k < 3; ++k) {
                const tinyobj::index_t& ix = idx[3 * f + k];
                const VertexKey key{ix.vertex_index, have_normals ? ix.normal_index : -1,
                                    have_uvs ? ix.texcoord_index : -1};
                auto [it, inserted] = maps[mat].try_emplace(key, uint32_t(mesh.positions.size()));
                if (inserted) {
                    const auto v = std::size_t(std::max(key.v, 0));
                    mesh.positions.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1],
                                                attrib.vertices[3 * v + 2]);
                    if (have_normals) {
                        const auto n = std::size_t(std::max(key.n, 0));
                        mesh.normals.push_back(key.n >= 0 ? Vec3(attrib.normals[3 * n],
                                                                 attrib.normals[3 * n + 1],
                                                                 attrib.normals[3 * n + 2])
                                                          : Vec3(0.0f));
                    }
                    if (have_uvs) {
                        const auto t = std::size_t(std::max(key.t, 0));
                        // OBJ's v runs upwards; glTF's (ours) downwards from the image's top row.
                        mesh.uvs.push_back(key.t >= 0 ? Vec2(attrib.texcoords[2 * t],
                                                             1.0f - attrib.texcoords[2 * t + 1])
                                                      : Vec2(0.0f));
                    }
                }
                mesh.indices.push_back(it->second);
            }
        }
    }
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        if (meshes[m].indices.empty()) continue;
        meshes[m].material = int(m);
        meshes[m].name = scene_.materials[m].name;
        if (scene_.materials[m].normal_texture.valid()) compute_tangents(meshes[m]);
        Node node;
        node.name = meshes[m].name;
        node.meshes.push_back(int(scene_.meshes.size()));
        scene_.meshes.push_back(std::move(meshes[m]));
        scene_.nodes.push_back(std::move(node));
    }
}

Result<SceneModel> ObjImporter::run(const std::string& text) {
    std::istringstream stream(text);
    tinyobj::MaterialFileReader mtl_reader(dir_.empty() ? std::string("./") : dir_ + "/");
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, &mtl_reader, true))
        return make_error(ErrorCode::parse_error, "{}: {}", path_,
                          err.empty() ? "not a valid OBJ file" : err.substr(0, err.find('\n')));
    if (!warn.empty()) spdlog::warn("{}: {}", path_, warn.substr(0, warn.find('\n')));
    if (attrib.vertices.empty() || shapes.empty())
        return make_error(ErrorCode::parse_error, "{}: no geometry (not an OBJ file?)", path_);
    for (const auto& m : materials)
        scene_.materials.push_back(convert_material(m));
    Material fallback;  // for faces without usemtl
    fallback.name = "obj-default";
    fallback.metallic_factor = 0.0f;
    fallback.specular_factor = 0.0f;
    scene_.materials.push_back(std::move(fallback));
    for (const auto& shape : shapes)
        for (const auto& ix : shape.mesh.indices)
            if (ix.vertex_index < 0 ||
                std::size_t(ix.vertex_index) * 3 + 2 >= attrib.vertices.size() ||
                (ix.normal_index >= 0 &&
                 std::size_t(ix.normal_index) * 3 + 2 >= attrib.normals.size()) ||
                (ix.texcoord_index >= 0 &&
                 std::size_t(ix.texcoord_index) * 2 + 1 >= attrib.texcoords.size()))
                return make_error(ErrorCode::parse_error,
                                  "{}: shape \"{}\": face refers to a missing vertex, normal or UV",
                                  path_, shape.name);
    build_meshes(attrib, shapes);
    scene_.name = path_;
    flatten_nodes(scene_);
    return std::move(scene_);
}

}  // namespace

Result<SceneModel> load_obj(const std::string& path) {
    auto text = read_file_maybe_gzip(path);
    if (!text) return text.error();
    return ObjImporter(path).run(*text);
}

}  // namespace pathfarm
