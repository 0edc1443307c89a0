// Commit <-> protobuf. Arrays travel as raw little-endian bytes; bulk payloads as chunked blobs.
#include "common/commit/commit_codec.h"

#include <bit>
#include <cstring>
#include <map>

#include "pathfarm/wire/v1/commit.pb.h"

namespace pathfarm {
namespace {

namespace pb = ::pathfarm::wire::v1;
static_assert(std::endian::native == std::endian::little, "wire arrays are little endian");

template <class... Ts>
struct Overloaded : Ts... {
    using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

template <typename T>
std::string to_bytes(const std::vector<T>& v) {
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <typename T>
bool from_bytes(const std::string& bytes, std::vector<T>& out) {
    if (bytes.size() % sizeof(T) != 0) return false;
    out.resize(bytes.size() / sizeof(T));
    if (!bytes.empty()) std::memcpy(out.data(), bytes.data(), bytes.size());
    return true;
}

std::string mat_bytes(const Mat4& m) {
    return std::string(reinterpret_cast<const char*>(&m[0][0]), sizeof(Mat4));
}
bool mat_from(const std::string& b, Mat4& m) {
    if (b.size() != sizeof(Mat4)) return false;
    std::memcpy(&m[0][0], b.data(), sizeof(Mat4));
    return true;
}

void put_floats(google::protobuf::RepeatedField<float>* f, const float* v, int n) {
    for (int i = 0; i < n; ++i)
        f->Add(v[i]);
}
template <int N>
bool get_floats(const google::protobuf::RepeatedField<float>& f, float* v) {
    if (f.size() != N) return false;
    for (int i = 0; i < N; ++i)
        v[i] = f[i];
    return true;
}

void put_ref(pb::TextureRefData* d, const TextureRef& r) {
    d->set_texture(r.texture);
    d->set_texcoord(uint32_t(r.texcoord));
    if (r.transform.identity()) return;
    put_floats(d->mutable_uv_offset(), &r.transform.offset[0], 2);
    d->set_uv_rotation(r.transform.rotation);
    put_floats(d->mutable_uv_scale(), &r.transform.scale[0], 2);
}
bool get_ref(const pb::TextureRefData& d, TextureRef& r) {
    r = TextureRef{d.texture(), int(d.texcoord()), {}};
    r.transform.rotation = d.uv_rotation();
    if (d.uv_offset().empty() && d.uv_scale().empty()) return true;
    return get_floats<2>(d.uv_offset(), &r.transform.offset[0]) &&
           get_floats<2>(d.uv_scale(), &r.transform.scale[0]);
}

void put_material(pb::MaterialData* d, const Material& m) {
    d->set_name(m.name);
    put_floats(d->mutable_base_color_factor(), &m.base_color_factor[0], 4);
    put_ref(d->mutable_base_color_texture(), m.base_color_texture);
    d->set_metallic_factor(m.metallic_factor);
    d->set_roughness_factor(m.roughness_factor);
    put_ref(d->mutable_metallic_roughness_texture(), m.metallic_roughness_texture);
    put_ref(d->mutable_normal_texture(), m.normal_texture);
    d->set_normal_scale(m.normal_scale);
    put_floats(d->mutable_emissive_factor(), &m.emissive_factor[0], 3);
    d->set_emissive_strength(m.emissive_strength);
    put_ref(d->mutable_emissive_texture(), m.emissive_texture);
    d->set_transmission_factor(m.transmission_factor);
    d->set_ior(m.ior);
    d->set_specular_factor(m.specular_factor);
    put_floats(d->mutable_specular_color_factor(), &m.specular_color_factor[0], 3);
    put_floats(d->mutable_attenuation_color(), &m.attenuation_color[0], 3);
    d->set_attenuation_distance(m.attenuation_distance);
    d->set_double_sided(m.double_sided);
    d->set_alpha_mode(uint32_t(m.alpha_mode));
    d->set_alpha_cutoff(m.alpha_cutoff);
}

bool get_material(const pb::MaterialData& d, Material& m) {
    m.name = d.name();
    m.metallic_factor = d.metallic_factor();
    m.roughness_factor = d.roughness_factor();
    m.normal_scale = d.normal_scale();
    m.emissive_strength = d.emissive_strength();
    if (d.alpha_mode() >= uint32_t(kAlphaModeCount)) return false;
    m.alpha_mode = AlphaMode(d.alpha_mode());
    m.alpha_cutoff = d.alpha_cutoff();
    m.transmission_factor = d.transmission_factor();
    m.ior = d.ior();
    m.specular_factor = d.specular_factor();
    m.attenuation_distance = d.attenuation_distance();
    m.double_sided = d.double_sided();
    return get_ref(d.base_color_texture(), m.base_color_texture) &&
           get_ref(d.metallic_roughness_texture(), m.metallic_roughness_texture) &&
           get_ref(d.normal_texture(), m.normal_texture) &&
           get_ref(d.emissive_texture(), m.emissive_texture) &&
           get_floats<4>(d.base_color_factor(), &m.base_color_factor[0]) &&
           get_floats<3>(d.emissive_factor(), &m.emissive_factor[0]) &&
           get_floats<3>(d.specular_color_factor(), &m.specular_color_factor[0]) &&
           get_floats<3>(d.attenuation_color(), &m.attenuation_color[0]);
}

pb::MeshData mesh_data(const Mesh& m) {
    pb::MeshData d;
    d.set_name(m.name);
    d.set_positions(to_bytes(m.positions));
    d.set_normals(to_bytes(m.normals));
    d.set_uvs(to_bytes(m.uvs));
    d.set_tangents(to_bytes(m.tangents));
    d.set_indices(to_bytes(m.indices));
    d.set_material(uint32_t(m.material));
    return d;
}

bool get_mesh(const pb::MeshData& d, Mesh& m) {
    m.name = d.name();
    m.material = int(d.material());
    return from_bytes(d.positions(), m.positions) && from_bytes(d.normals(), m.normals) &&
           from_bytes(d.uvs(), m.uvs) && from_bytes(d.tangents(), m.tangents) &&
           from_bytes(d.indices(), m.indices) && m.indices.size() % 3 == 0 &&
           (m.normals.empty() || m.normals.size() == m.positions.size()) &&
           (m.uvs.empty() || m.uvs.size() == m.positions.size()) &&
           (m.tangents.empty() || m.tangents.size() == m.positions.size());
}

pb::VertexRangeData range_data(const UpdateVertexRange& u) {
    pb::VertexRangeData d;
    d.set_positions(to_bytes(u.positions));
    d.set_normals(to_bytes(u.normals));
    d.set_tangents(to_bytes(u.tangents));
    return d;
}

class BlobWriter {
public:
    BlobWriter(uint64_t frame, std::size_t max_chunk)
        : frame_(frame), max_chunk_(std::max<std::size_t>(max_chunk, 1)) {}
    uint64_t add(const google::protobuf::MessageLite& message) {
        const uint64_t id = ++count_;
        const std::string bytes = message.SerializeAsString();
        std::size_t offset = 0;
        do {
            pb::BulkChunk chunk;
            chunk.set_frame(frame_);
            chunk.set_blob(id);
            chunk.set_offset(offset);
            chunk.set_total_bytes(bytes.size());
            const std::size_t n = std::min(max_chunk_, bytes.size() - offset);
            chunk.set_data(bytes.substr(offset, n));
            chunks_.push_back(chunk.SerializeAsString());
            offset += n;
        } while (offset < bytes.size());
        return id;
    }
    uint32_t count() const { return uint32_t(count_); }
    std::vector<std::string> take() { return std::move(chunks_); }

private:
    uint64_t frame_;
    std::size_t max_chunk_;
    uint64_t count_ = 0;
    std::vector<std::string> chunks_;
};

void encode_op(const CommitOp& op, pb::CommitOp& out, BlobWriter& blobs) {
    std::visit(
        Overloaded{
            [&](const SetInstance& o) {
                auto* w = out.mutable_set_instance();
                w->set_id(o.id);
                w->mutable_instance()->set_mesh(o.instance.mesh);
                w->mutable_instance()->set_transform(mat_bytes(o.instance.transform));
            },
            [&](const RemoveInstance& o) { out.mutable_remove_instance()->set_id(o.id); },
            [&](const AddMesh& o) {
                out.mutable_add_mesh()->set_id(o.id);
                out.mutable_add_mesh()->set_blob(blobs.add(mesh_data(o.mesh)));
            },
            [&](const RemoveMesh& o) { out.mutable_remove_mesh()->set_id(o.id); },
            [&](const UpdateVertexRange& o) {
                auto* w = out.mutable_update_vertex_range();
                w->set_mesh(o.mesh);
                w->set_first(o.first);
                pb::VertexRangeData d = range_data(o);
                if (d.ByteSizeLong() > kInlineVertexBytes)
                    w->set_blob(blobs.add(d));
                else
                    *w->mutable_inline_data() = std::move(d);
            },
            [&](const SetMaterial& o) {
                out.mutable_set_material()->set_id(o.id);
                put_material(out.mutable_set_material()->mutable_material(), o.material);
            },
            [&](const RemoveMaterial& o) { out.mutable_remove_material()->set_id(o.id); },
            [&](const AddImage& o) {
                pb::ImageData d;
                d.set_name(o.image.name);
                d.set_width(uint32_t(o.image.width));
                d.set_height(uint32_t(o.image.height));
                d.set_rgba(to_bytes(o.image.rgba));
                out.mutable_add_image()->set_id(o.id);
                out.mutable_add_image()->set_blob(blobs.add(d));
            },
            [&](const RemoveImage& o) { out.mutable_remove_image()->set_id(o.id); },
            [&](const SetTexture& o) {
                auto* t = out.mutable_set_texture();
                t->set_id(o.id);
                t->mutable_texture()->set_image(o.texture.image);
                t->mutable_texture()->set_filter(uint32_t(o.texture.sampler.filter));
                t->mutable_texture()->set_wrap_s(uint32_t(o.texture.sampler.wrap_s));
                t->mutable_texture()->set_wrap_t(uint32_t(o.texture.sampler.wrap_t));
            },
            [&](const RemoveTexture& o) { out.mutable_remove_texture()->set_id(o.id); },
            [&](const SetCamera& o) {
                auto* c = out.mutable_set_camera();
                c->set_id(o.id);
                c->set_active(o.active);
                c->mutable_camera()->set_name(o.camera.name);
                c->mutable_camera()->set_camera_to_world(mat_bytes(o.camera.camera_to_world));
                c->mutable_camera()->set_yfov_radians(o.camera.yfov_radians);
            },
            [&](const SetEnvironment& o) {
                auto* e = out.mutable_set_environment()->mutable_environment();
                e->set_sky(uint32_t(o.environment.sky));
                put_floats(e->mutable_sun_direction(), &o.environment.sun_direction[0], 3);
                e->set_turbidity(o.environment.turbidity);
                e->set_sun_scale(o.environment.sun_scale);
            },
            [&](const SetMeshBvh& o) {
                auto* b = out.mutable_set_mesh_bvh();
                b->set_mesh(o.mesh);
                b->set_node_count(o.node_count);
                b->set_first_node(o.first_node);
                pb::BvhPayload d;
                d.set_nodes(to_bytes(o.nodes));
                d.set_prim_indices(to_bytes(o.prim_indices));
                if (d.ByteSizeLong() > kInlineVertexBytes)
                    b->set_blob(blobs.add(d));
                else
                    *b->mutable_inline_data() = std::move(d);
            },
            [&](const SetTopLevelBvh& o) {
                auto* b = out.mutable_set_top_level_bvh();
                pb::BvhPayload d;
                d.set_nodes(to_bytes(o.nodes));
                d.set_prim_indices(to_bytes(o.prim_indices));
                d.set_instance_ids(to_bytes(o.instance_ids));
                if (d.ByteSizeLong() > kInlineVertexBytes)
                    b->set_blob(blobs.add(d));
                else
                    *b->mutable_inline_data() = std::move(d);
            },
            [&](const SetSettings& o) {
                auto* s = out.mutable_set_settings()->mutable_settings();
                s->set_width(o.settings.width);
                s->set_height(o.settings.height);
                s->set_spp(o.settings.spp);
                s->set_max_depth(o.settings.max_depth);
                s->set_seed(o.settings.seed);
            },
        },
        op);
}

}  // namespace

std::size_t EncodedCommit::total_bytes() const {
    std::size_t n = commit.size();
    for (const std::string& c : chunks)
        n += c.size();
    return n;
}

EncodedCommit encode_commit(const Commit& commit, std::size_t max_chunk_bytes) {
    pb::Commit w;
    w.set_frame(commit.frame);
    w.set_base_commit(commit.base_commit);
    w.set_is_snapshot(commit.is_snapshot);
    BlobWriter blobs(commit.frame, max_chunk_bytes);
    for (const CommitOp& op : commit.ops)
        encode_op(op, *w.add_ops(), blobs);
    w.set_blob_count(blobs.count());
    return EncodedCommit{w.SerializeAsString(), blobs.take()};
}

namespace {

// Reassembles blobs from their chunks: each must arrive whole, in order, with one total size.
Result<std::map<uint64_t, std::string>> assemble_blobs(const std::vector<std::string>& chunks,
                                                       uint64_t frame, uint32_t blob_count) {
    std::map<uint64_t, std::string> blobs;
    std::map<uint64_t, uint64_t> totals;
    for (const std::string& bytes : chunks) {
        pb::BulkChunk c;
        if (!c.ParseFromString(bytes))
            return make_error(ErrorCode::parse_error, "commit {}: malformed bulk chunk", frame);
        if (c.frame() != frame || c.blob() == 0 || c.blob() > blob_count)
            return make_error(ErrorCode::parse_error,
                              "commit {}: chunk of blob {} (frame {}) does not belong here", frame,
                              c.blob(), c.frame());
        std::string& blob = blobs[c.blob()];
        const auto [it, first] = totals.emplace(c.blob(), c.total_bytes());
        if (c.offset() != blob.size() || it->second != c.total_bytes() ||
            blob.size() + c.data().size() > c.total_bytes())
            return make_error(ErrorCode::parse_error,
                              "commit {}: blob {} chunk out of order or oversized", frame,
                              c.blob());
        blob += c.data();
    }
    if (blobs.size() != blob_count)
        return make_error(ErrorCode::parse_error, "commit {}: {} of {} blobs arrived", frame,
                          blobs.size(), blob_count);
    for (const auto& [id, blob] : blobs)
        if (blob.size() != totals[id])
            return make_error(ErrorCode::parse_error, "commit {}: blob {} incomplete", frame, id);
    return blobs;
}

template <typename Message>
bool parse_blob(const std::map<uint64_t, std::string>& blobs, uint64_t id, Message& m) {
    const auto it = blobs.find(id);
    return it != blobs.end() && m.ParseFromString(it->second);
}

bool decode_range(const pb::VertexRangeData& d, UpdateVertexRange& u) {
    return from_bytes(d.positions(), u.positions) && from_bytes(d.normals(), u.normals) &&
           from_bytes(d.tangents(), u.tangents);
}

// Returns false on malformed content; the caller names the op.
bool decode_op(const pb::CommitOp& w, const std::map<uint64_t, std::string>& blobs, CommitOp& out) {
    switch (w.op_case()) {
        case pb::CommitOp::kSetInstance: {
            SetInstance o{w.set_instance().id(), {w.set_instance().instance().mesh(), Mat4(1.0f)}};
            out = o;
            return mat_from(w.set_instance().instance().transform(),
                            std::get<SetInstance>(out).instance.transform);
        }
        case pb::CommitOp::kRemoveInstance:
            out = RemoveInstance{w.remove_instance().id()};
            return true;
        case pb::CommitOp::kAddMesh: {
            pb::MeshData d;
            AddMesh o{w.add_mesh().id(), {}};
            if (!parse_blob(blobs, w.add_mesh().blob(), d) || !get_mesh(d, o.mesh)) return false;
            out = std::move(o);
            return true;
        }
        case pb::CommitOp::kRemoveMesh:
            out = RemoveMesh{w.remove_mesh().id()};
            return true;
        case pb::CommitOp::kUpdateVertexRange: {
            const auto& v = w.update_vertex_range();
            UpdateVertexRange o{v.mesh(), v.first(), {}, {}, {}};
            pb::VertexRangeData d;
            if (v.blob() != 0 ? !parse_blob(blobs, v.blob(), d) : false) return false;
            if (!decode_range(v.blob() != 0 ? d : v.inline_data(), o)) return false;
            out = std::move(o);
            return true;
        }
        case pb::CommitOp::kSetMaterial: {
            SetMaterial o{w.set_material().id(), {}};
            if (!get_material(w.set_material().material(), o.material)) return false;
            out = std::move(o);
            return true;
        }
        case pb::CommitOp::kRemoveMaterial:
            out = RemoveMaterial{w.remove_material().id()};
            return true;
        case pb::CommitOp::kAddImage: {
            pb::ImageData d;
            if (!parse_blob(blobs, w.add_image().blob(), d)) return false;
            AddImage o{w.add_image().id(), Image{d.name(), int(d.width()), int(d.height()), {}}};
            if (!from_bytes(d.rgba(), o.image.rgba)) return false;
            out = std::move(o);
            return true;
        }
        case pb::CommitOp::kRemoveImage:
            out = RemoveImage{w.remove_image().id()};
            return true;
        case pb::CommitOp::kSetTexture: {
            const auto& t = w.set_texture().texture();
            if (t.filter() > 1 || t.wrap_s() > 2 || t.wrap_t() > 2) return false;
            out =
                SetTexture{w.set_texture().id(),
                           Texture{t.image(), Sampler{FilterMode(t.filter()), WrapMode(t.wrap_s()),
                                                      WrapMode(t.wrap_t())}}};
            return true;
        }
        case pb::CommitOp::kRemoveTexture:
            out = RemoveTexture{w.remove_texture().id()};
            return true;
        case pb::CommitOp::kSetCamera: {
            const auto& c = w.set_camera();
            SetCamera o{c.id(), Camera{c.camera().name(), Mat4(1.0f), c.camera().yfov_radians()},
                        c.active()};
            if (!mat_from(c.camera().camera_to_world(), o.camera.camera_to_world)) return false;
            out = std::move(o);
            return true;
        }
        case pb::CommitOp::kSetEnvironment: {
            const auto& e = w.set_environment().environment();
            SetEnvironment o;
            if (e.sky() > 2 || !get_floats<3>(e.sun_direction(), &o.environment.sun_direction[0]))
                return false;
            o.environment.sky = SkyMode(e.sky());
            o.environment.turbidity = e.turbidity();
            o.environment.sun_scale = e.sun_scale();
            out = o;
            return true;
        }
        case pb::CommitOp::kSetMeshBvh: {
            const auto& b = w.set_mesh_bvh();
            pb::BvhPayload d;
            if (b.blob() != 0 && !parse_blob(blobs, b.blob(), d)) return false;
            const pb::BvhPayload& payload = b.blob() != 0 ? d : b.inline_data();
            SetMeshBvh o{b.mesh(), b.node_count(), b.first_node(), {}, {}};
            if (!from_bytes(payload.nodes(), o.nodes) ||
                !from_bytes(payload.prim_indices(), o.prim_indices))
                return false;
            out = std::move(o);
            return true;
        }
        case pb::CommitOp::kSetTopLevelBvh: {
            const auto& b = w.set_top_level_bvh();
            pb::BvhPayload d;
            if (b.blob() != 0 && !parse_blob(blobs, b.blob(), d)) return false;
            const pb::BvhPayload& payload = b.blob() != 0 ? d : b.inline_data();
            SetTopLevelBvh o;
            if (!from_bytes(payload.nodes(), o.nodes) ||
                !from_bytes(payload.prim_indices(), o.prim_indices) ||
                !from_bytes(payload.instance_ids(), o.instance_ids))
                return false;
            out = std::move(o);
            return true;
        }
        case pb::CommitOp::kSetSettings: {
            const auto& s = w.set_settings().settings();
            out = SetSettings{
                RenderSettings{s.width(), s.height(), s.spp(), s.max_depth(), s.seed()}};
            return true;
        }
        default:
            return false;
    }
}

}  // namespace

Result<Commit> decode_commit(const std::string& commit_bytes,
                             const std::vector<std::string>& chunks) {
    pb::Commit w;
    if (!w.ParseFromString(commit_bytes))
        return make_error(ErrorCode::parse_error, "malformed commit message");
    auto blobs = assemble_blobs(chunks, w.frame(), w.blob_count());
    if (!blobs) return blobs.error();
    Commit c;
    c.frame = w.frame();
    c.base_commit = w.base_commit();
    c.is_snapshot = w.is_snapshot();
    c.ops.resize(std::size_t(w.ops_size()));
    for (int i = 0; i < w.ops_size(); ++i)
        if (!decode_op(w.ops(i), *blobs, c.ops[std::size_t(i)]))
            return make_error(ErrorCode::parse_error, "commit {}: op {} is malformed", c.frame, i);
    return c;
}

}  // namespace pathfarm
