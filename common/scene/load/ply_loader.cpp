// PLY triangle meshes (ascii, binary little and big endian; gzip through zlib). Debian 12 has
// no PLY library besides Assimp, so this reads the subset scanners produce: a vertex element
// with x, y, z (plus optional nx, ny, nz) and a face element with a vertex index list; any
// other property or element is skipped by type.
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "common/scene/load/file_read.h"
#include "common/scene/load/scene_loader.h"

namespace pathfarm {
namespace {

enum class PlyFormat { ascii, binary_le, binary_be };

struct PlyProperty {
    std::string name;
    std::string type;        // scalar type, or the item type of a list
    std::string count_type;  // non-empty for lists
};

struct PlyElement {
    std::string name;
    std::size_t count = 0;
    std::vector<PlyProperty> properties;
};

int type_size(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" ||
        t == "float32")
        return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

class PlyReader {
public:
    PlyReader(std::string path, const std::string& data) : path_(std::move(path)), data_(data) {}
    Result<SceneModel> run();

private:
    Status parse_header();
    bool read_value(const std::string& type, double& out);
    Status read_element(const PlyElement& e, Mesh& mesh);
    static Status add_face(const std::vector<double>& values, Mesh& mesh);
    Error error(const std::string& what) const {
        return make_error(ErrorCode::parse_error, "{}: {}", path_, what);
    }

    std::string path_;
    const std::string& data_;
    std::size_t pos_ = 0;
    PlyFormat format_ = PlyFormat::ascii;
    std::vector<PlyElement> elements_;
};

Status PlyReader::parse_header() {
    const std::size_t end = data_.find("end_header");
    if (data_.rfind("ply", 0) != 0 || end == std::string::npos)
        return error("not a PLY file (missing 'ply' or 'end_header')");
    std::istringstream header(data_.substr(0, end));
    std::string line;
    while (std::getline(header, line)) {
        std::istringstream ls(line);
        std::string word;
        ls >> word;
        if (word == "format") {
            std::string f;
            ls >> f;
            if (f == "ascii")
                format_ = PlyFormat::ascii;
            else if (f == "binary_little_endian")
                format_ = PlyFormat::binary_le;
            else if (f == "binary_big_endian")
                format_ = PlyFormat::binary_be;
            else
                return error("unknown format '" + f + "'");
        } else if (word == "element") {
            PlyElement e;
            long long count = -1;  // ">> size_t" would take "-1" as 2^64 - 1
            ls >> e.name >> count;
            if (ls.fail() || count < 0) return error("malformed element line '" + line + "'");
            e.count = std::size_t(count);
            elements_.push_back(std::move(e));
        } else if (word == "property") {
            if (elements_.empty()) return error("property before any element");
            PlyProperty p;
            std::string t;
            ls >> t;
            if (t == "list")
                ls >> p.count_type >> p.type >> p.name;
            else {
                p.type = t;
                ls >> p.name;
            }
            if (ls.fail() || type_size(p.type) == 0 ||
                (!p.count_type.empty() && type_size(p.count_type) == 0))
                return error("malformed property line '" + line + "'");
            elements_.back().properties.push_back(std::move(p));
        }
    }
    pos_ = data_.find('\n', end);
    pos_ = pos_ == std::string::npos ? data_.size() : pos_ + 1;
    return {};
}

bool PlyReader::read_value(const std::string& type, double& out) {
    if (format_ == PlyFormat::ascii) {
        while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_])))
            ++pos_;
        if (pos_ >= data_.size()) return false;
        const char* begin = data_.data() + pos_;
        const auto [ptr, ec] = std::from_chars(begin, data_.data() + data_.size(), out);
        if (ec != std::errc()) return false;
        pos_ += std::size_t(ptr - begin);
        return true;
    }
    const int size = type_size(type);
    if (pos_ + size > data_.size()) return false;
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, size);
    pos_ += size;
    if ((format_ == PlyFormat::binary_be) == (std::endian::native == std::endian::little))
        std::reverse(b, b + size);
    if (type == "char" || type == "int8")
        out = static_cast<int8_t>(b[0]);
    else if (type == "uchar" || type == "uint8")
        out = b[0];
    else if (type == "short" || type == "int16") {
        int16_t v;
        std::memcpy(&v, b, 2);
        out = v;
    } else if (type == "ushort" || type == "uint16") {
        uint16_t v;
        std::memcpy(&v, b, 2);
        out = v;
    } else if (type == "int" || type == "int32") {
        int32_t v;
        std::memcpy(&v, b, 4);
        out = v;
    } else if (type == "uint" || type == "uint32") {
        uint32_t v;
        std::memcpy(&v, b, 4);
        out = v;
    } else if (type == "float" || type == "float32") {
        float v;
        std::memcpy(&v, b, 4);
        out = v;
    } else {
        double v;
        std::memcpy(&v, b, 8);
        out = v;
    }
    return true;
}

Status PlyReader::read_element(const PlyElement& e, Mesh& mesh) {
    const bool is_vertex = e.name == "vertex";
    const bool is_face = e.name == "face";
    std::vector<double> values;
    if (e.properties.empty() && e.count > 0)  // nothing to read: its count could be anything
        return error(fmt::format("element '{}' has no properties", e.name));
    for (std::size_t i = 0; i < e.count; ++i) {
        Vec3 p(0.0f), n(0.0f);
        bool has_n = false;
        for (const PlyProperty& prop : e.properties) {
            double v = 0.0;
            if (prop.count_type.empty()) {
                if (!read_value(prop.type, v))
                    return error(fmt::format(
                        "element '{}' {} of {}: unexpected end of data (truncated file?)", e.name,
                        i, e.count));
                const int axis = prop.name == "x"   ? 0
                                 : prop.name == "y" ? 1
                                 : prop.name == "z" ? 2
                                                    : -1;
                const int naxis = prop.name == "nx"   ? 0
                                  : prop.name == "ny" ? 1
                                  : prop.name == "nz" ? 2
                                                      : -1;
                if (axis >= 0) p[axis] = float(v);
                if (naxis >= 0) {
                    n[naxis] = float(v);
                    has_n = true;
                }
                continue;
            }
            double count = 0.0;
            // Every value takes a byte at least: a list longer than what is left is not one
            // (written so that a NaN count fails too).
            if (!read_value(prop.count_type, count) ||
                !(count >= 0.0 && count <= 1e6 && count <= double(data_.size() - pos_)))
                return error(
                    fmt::format("element '{}' {}: bad list length (truncated file?)", e.name, i));
            values.resize(std::size_t(count));
            for (double& x : values)
                if (!read_value(prop.type, x))
                    return error(fmt::format(
                        "element '{}' {} of {}: unexpected end of data (truncated file?)", e.name,
                        i, e.count));
            if (is_face && (prop.name == "vertex_indices" || prop.name == "vertex_index"))
                if (Status st = add_face(values, mesh); !st)
                    return error(fmt::format("element '{}' {}: {}", e.name, i, st.error().message));
        }
        if (is_vertex) {
            mesh.positions.push_back(p);
            if (has_n) mesh.normals.push_back(n);
        }
    }
    return {};
}

// Fan-triangulates one polygon. Any double may come from the file: only whole numbers in
// uint32 range are indices (out-of-range ones are left to validation, which names them).
Status PlyReader::add_face(const std::vector<double>& values, Mesh& mesh) {
    for (const double x : values)
        if (!(x >= 0.0 && x <= 4294967295.0) || x != std::floor(x))
            return make_error(ErrorCode::parse_error, "vertex index {} is not one", x);
    for (std::size_t k = 2; k < values.size(); ++k)
        mesh.indices.insert(mesh.indices.end(),
                            {uint32_t(values[0]), uint32_t(values[k - 1]), uint32_t(values[k])});
    return {};
}

Result<SceneModel> PlyReader::run() {
    if (Status s = parse_header(); !s) return s.error();
    Mesh mesh;
    mesh.name = std::filesystem::path(path_).filename().string();
    for (const PlyElement& e : elements_)
        if (Status s = read_element(e, mesh); !s) return s.error();
    if (mesh.positions.empty()) return error("no vertex element");
    for (uint32_t i : mesh.indices)
        if (i >= mesh.positions.size())
            return error(
                fmt::format("face index {} out of range ({} vertices)", i, mesh.positions.size()));
    SceneModel scene;
    scene.name = path_;
    Material grey;
    grey.name = "ply-default";
    grey.base_color_factor = Vec4(0.75f, 0.75f, 0.75f, 1.0f);
    grey.metallic_factor = 0.0f;
    grey.roughness_factor = 0.5f;
    scene.materials.push_back(std::move(grey));
    scene.meshes.push_back(std::move(mesh));
    Node node;
    node.name = scene.meshes[0].name;
    node.meshes.push_back(0);
    scene.nodes.push_back(std::move(node));
    flatten_nodes(scene);
    return scene;
}

}  // namespace

Result<SceneModel> load_ply(const std::string& path) {
    auto data = read_file_maybe_gzip(path);
    if (!data) return data.error();
    return PlyReader(path, *data).run();
}

}  // namespace pathfarm
