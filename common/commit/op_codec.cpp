// The commit ops on the wire (codec_internal.h): for every op its encode (put) and its decode
// (get) side by side, and one dispatch each way.
#include "common/commit/codec_internal.h"

namespace pathfarm::codec {
namespace {

namespace pb = commit_pb;

void put(const SetInstance& o, pb::CommitOp& out, BlobWriter&) {
    auto* w = out.mutable_set_instance();
    w->set_id(o.id);
    w->mutable_instance()->set_mesh(o.instance.mesh);
    w->mutable_instance()->set_transform(mat_bytes(o.instance.transform));
    w->mutable_instance()->set_dynamic(o.instance.dynamic);
}
Status get(const pb::SetInstance& w, const Blobs&, SetInstance& o) {
    o = SetInstance{w.id(), {w.instance().mesh(), Mat4(1.0f), w.instance().dynamic()}};
    return mat_from(w.instance().transform(), o.instance.transform, "transform");
}

void put(const RemoveInstance& o, pb::CommitOp& out, BlobWriter&) {
    out.mutable_remove_instance()->set_id(o.id);
}
Status get(const pb::RemoveInstance& w, const Blobs&, RemoveInstance& o) {
    o.id = w.id();
    return {};
}

void put(const AddMesh& o, pb::CommitOp& out, BlobWriter& blobs) {
    out.mutable_add_mesh()->set_id(o.id);
    out.mutable_add_mesh()->set_blob(blobs.add(mesh_data(o.mesh)));
}
Status get(const pb::AddMesh& w, const Blobs& blobs, AddMesh& o) {
    o.id = w.id();
    pb::MeshData d;
    if (Status s = parse_blob(blobs, w.blob(), d); !s) return s;
    return get_mesh(d, o.mesh);
}

void put(const RemoveMesh& o, pb::CommitOp& out, BlobWriter&) {
    out.mutable_remove_mesh()->set_id(o.id);
}
Status get(const pb::RemoveMesh& w, const Blobs&, RemoveMesh& o) {
    o.id = w.id();
    return {};
}

void put(const UpdateVertexRange& o, pb::CommitOp& out, BlobWriter& blobs) {
    auto* w = out.mutable_update_vertex_range();
    w->set_mesh(o.mesh);
    w->set_first(o.first);
    pb::VertexRangeData d;
    d.set_positions(to_bytes(o.positions));
    d.set_normals(to_bytes(o.normals));
    d.set_tangents(to_bytes(o.tangents));
    put_inline_or_blob(w, std::move(d), blobs);
}
Status get(const pb::UpdateVertexRange& w, const Blobs& blobs, UpdateVertexRange& o) {
    o = UpdateVertexRange{w.mesh(), w.first(), {}, {}, {}};
    pb::VertexRangeData d;
    if (Status s = get_inline_or_blob(w, blobs, d); !s) return s;
    for (Status s : {from_bytes(d.positions(), o.positions, "positions"),
                     from_bytes(d.normals(), o.normals, "normals"),
                     from_bytes(d.tangents(), o.tangents, "tangents")})
        if (!s) return s;
    return {};
}

void put(const SetMaterial& o, pb::CommitOp& out, BlobWriter&) {
    out.mutable_set_material()->set_id(o.id);
    put_material(out.mutable_set_material()->mutable_material(), o.material);
}
Status get(const pb::SetMaterial& w, const Blobs&, SetMaterial& o) {
    o.id = w.id();
    return get_material(w.material(), o.material);
}

void put(const RemoveMaterial& o, pb::CommitOp& out, BlobWriter&) {
    out.mutable_remove_material()->set_id(o.id);
}
Status get(const pb::RemoveMaterial& w, const Blobs&, RemoveMaterial& o) {
    o.id = w.id();
    return {};
}

void put(const AddImage& o, pb::CommitOp& out, BlobWriter& blobs) {
    out.mutable_add_image()->set_id(o.id);
    out.mutable_add_image()->set_blob(blobs.add(image_data(o.image)));
}
Status get(const pb::AddImage& w, const Blobs& blobs, AddImage& o) {
    o.id = w.id();
    pb::ImageData d;
    if (Status s = parse_blob(blobs, w.blob(), d); !s) return s;
    return get_image(d, o.image);
}

void put(const RemoveImage& o, pb::CommitOp& out, BlobWriter&) {
    out.mutable_remove_image()->set_id(o.id);
}
Status get(const pb::RemoveImage& w, const Blobs&, RemoveImage& o) {
    o.id = w.id();
    return {};
}

void put(const SetTexture& o, pb::CommitOp& out, BlobWriter&) {
    out.mutable_set_texture()->set_id(o.id);
    put_texture(out.mutable_set_texture()->mutable_texture(), o.texture);
}
Status get(const pb::SetTexture& w, const Blobs&, SetTexture& o) {
    o.id = w.id();
    return get_texture(w.texture(), o.texture);
}

void put(const RemoveTexture& o, pb::CommitOp& out, BlobWriter&) {
    out.mutable_remove_texture()->set_id(o.id);
}
Status get(const pb::RemoveTexture& w, const Blobs&, RemoveTexture& o) {
    o.id = w.id();
    return {};
}

void put(const SetCamera& o, pb::CommitOp& out, BlobWriter&) {
    auto* c = out.mutable_set_camera();
    c->set_id(o.id);
    c->set_active(o.active);
    put_camera(c->mutable_camera(), o.camera);
}
Status get(const pb::SetCamera& w, const Blobs&, SetCamera& o) {
    o.id = w.id();
    o.active = w.active();
    return get_camera(w.camera(), o.camera);
}

void put(const SetEnvironment& o, pb::CommitOp& out, BlobWriter&) {
    put_environment(out.mutable_set_environment()->mutable_environment(), o.environment);
}
Status get(const pb::SetEnvironment& w, const Blobs&, SetEnvironment& o) {
    return get_environment(w.environment(), o.environment);
}

void put(const SetSettings& o, pb::CommitOp& out, BlobWriter&) {
    put_settings(out.mutable_set_settings()->mutable_settings(), o.settings);
}
Status get(const pb::SetSettings& w, const Blobs&, SetSettings& o) {
    o.settings = get_settings(w.settings());
    return {};
}

void put(const SetMeshBvh& o, pb::CommitOp& out, BlobWriter& blobs) {
    auto* b = out.mutable_set_mesh_bvh();
    b->set_mesh(o.mesh);
    b->set_node_count(o.node_count);
    b->set_first_node(o.first_node);
    pb::BvhPayload d;
    d.set_nodes(to_bytes(o.nodes));
    d.set_prim_indices(to_bytes(o.prim_indices));
    put_inline_or_blob(b, std::move(d), blobs);
}
Status get(const pb::SetMeshBvh& w, const Blobs& blobs, SetMeshBvh& o) {
    o = SetMeshBvh{w.mesh(), w.node_count(), w.first_node(), {}, {}};
    pb::BvhPayload d;
    if (Status s = get_inline_or_blob(w, blobs, d); !s) return s;
    if (Status s = from_bytes(d.nodes(), o.nodes, "nodes"); !s) return s;
    return from_bytes(d.prim_indices(), o.prim_indices, "prim_indices");
}

void put(const SetTopLevelBvh& o, pb::CommitOp& out, BlobWriter& blobs) {
    pb::BvhPayload d;
    d.set_nodes(to_bytes(o.nodes));
    d.set_prim_indices(to_bytes(o.prim_indices));
    d.set_instance_ids(to_bytes(o.instance_ids));
    put_inline_or_blob(out.mutable_set_top_level_bvh(), std::move(d), blobs);
}
Status get(const pb::SetTopLevelBvh& w, const Blobs& blobs, SetTopLevelBvh& o) {
    pb::BvhPayload d;
    if (Status s = get_inline_or_blob(w, blobs, d); !s) return s;
    for (Status s : {from_bytes(d.nodes(), o.nodes, "nodes"),
                     from_bytes(d.prim_indices(), o.prim_indices, "prim_indices"),
                     from_bytes(d.instance_ids(), o.instance_ids, "instance_ids")})
        if (!s) return s;
    return {};
}

// Decodes the op held in CommitOp field `Field` as an `Op`.
template <typename Op, auto Field>
Status decode_as(const pb::CommitOp& w, const Blobs& blobs, CommitOp& out) {
    Op o;
    if (Status s = get((w.*Field)(), blobs, o); !s) return s;
    out = std::move(o);
    return {};
}

struct OpEntry {
    pb::CommitOp::OpCase kind;
    const char* name;
    Status (*decode)(const pb::CommitOp&, const Blobs&, CommitOp&);
};
using C = pb::CommitOp;
constexpr OpEntry kOps[] = {
    {C::kSetInstance, "SetInstance", &decode_as<SetInstance, &C::set_instance>},
    {C::kRemoveInstance, "RemoveInstance", &decode_as<RemoveInstance, &C::remove_instance>},
    {C::kAddMesh, "AddMesh", &decode_as<AddMesh, &C::add_mesh>},
    {C::kRemoveMesh, "RemoveMesh", &decode_as<RemoveMesh, &C::remove_mesh>},
    {C::kUpdateVertexRange, "UpdateVertexRange",
     &decode_as<UpdateVertexRange, &C::update_vertex_range>},
    {C::kSetMaterial, "SetMaterial", &decode_as<SetMaterial, &C::set_material>},
    {C::kRemoveMaterial, "RemoveMaterial", &decode_as<RemoveMaterial, &C::remove_material>},
    {C::kAddImage, "AddImage", &decode_as<AddImage, &C::add_image>},
    {C::kRemoveImage, "RemoveImage", &decode_as<RemoveImage, &C::remove_image>},
    {C::kSetTexture, "SetTexture", &decode_as<SetTexture, &C::set_texture>},
    {C::kRemoveTexture, "RemoveTexture", &decode_as<RemoveTexture, &C::remove_texture>},
    {C::kSetCamera, "SetCamera", &decode_as<SetCamera, &C::set_camera>},
    {C::kSetEnvironment, "SetEnvironment", &decode_as<SetEnvironment, &C::set_environment>},
    {C::kSetSettings, "SetSettings", &decode_as<SetSettings, &C::set_settings>},
    {C::kSetMeshBvh, "SetMeshBvh", &decode_as<SetMeshBvh, &C::set_mesh_bvh>},
    {C::kSetTopLevelBvh, "SetTopLevelBvh", &decode_as<SetTopLevelBvh, &C::set_top_level_bvh>},
};

}  // namespace

void encode_op(const CommitOp& op, pb::CommitOp& out, BlobWriter& blobs) {
    std::visit([&](const auto& o) { put(o, out, blobs); }, op);
}

Status decode_op(const pb::CommitOp& w, const Blobs& blobs, CommitOp& out, const char*& name) {
    for (const OpEntry& e : kOps)
        if (e.kind == w.op_case()) {
            name = e.name;
            return e.decode(w, blobs, out);
        }
    name = "(unset)";
    return make_error(ErrorCode::parse_error, "no op, or one this build does not know");
}

}  // namespace pathfarm::codec
