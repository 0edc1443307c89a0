// The commit codec's fields (codec_internal.h): each encode beside its decode, and decode errors
// that name the field.
#include "common/commit/codec_internal.h"

namespace pathfarm::codec {
namespace {

void put_floats(google::protobuf::RepeatedField<float>* f, const float* v, int n) {
    for (int i = 0; i < n; ++i)
        f->Add(v[i]);
}
template <int N>
Status get_floats(const google::protobuf::RepeatedField<float>& f, float* v, const char* field) {
    if (f.size() != N)
        return make_error(ErrorCode::parse_error, "{}: {} values, not {}", field, f.size(), N);
    for (int i = 0; i < N; ++i)
        v[i] = f[i];
    return {};
}

Status check_enum(uint32_t value, int count, const char* field) {
    if (value < uint32_t(count)) return {};
    return make_error(ErrorCode::parse_error, "{}: {} is not one of the {} values", field, value,
                      count);
}

void put_ref(commit_pb::TextureRefData* d, const TextureRef& r) {
    d->set_texture(r.texture);
    d->set_texcoord(uint32_t(r.texcoord));
    if (r.transform.identity()) return;
    put_floats(d->mutable_uv_offset(), &r.transform.offset[0], 2);
    d->set_uv_rotation(r.transform.rotation);
    put_floats(d->mutable_uv_scale(), &r.transform.scale[0], 2);
}
Status get_ref(const commit_pb::TextureRefData& d, TextureRef& r, const char* field) {
    r = TextureRef{d.texture(), int(d.texcoord()), {}};
    r.transform.rotation = d.uv_rotation();
    if (d.uv_offset().empty() && d.uv_scale().empty()) return {};  // the identity
    if (Status s = get_floats<2>(d.uv_offset(), &r.transform.offset[0], "uv_offset"); !s)
        return make_error(ErrorCode::parse_error, "{}: {}", field, s.error().message);
    if (Status s = get_floats<2>(d.uv_scale(), &r.transform.scale[0], "uv_scale"); !s)
        return make_error(ErrorCode::parse_error, "{}: {}", field, s.error().message);
    return {};
}

}  // namespace

std::string mat_bytes(const Mat4& m) {
    return std::string(reinterpret_cast<const char*>(&m[0][0]), sizeof(Mat4));
}
Status mat_from(const std::string& bytes, Mat4& m, const char* field) {
    if (bytes.size() != sizeof(Mat4))
        return make_error(ErrorCode::parse_error, "{}: {} bytes, not {}", field, bytes.size(),
                          sizeof(Mat4));
    std::memcpy(&m[0][0], bytes.data(), sizeof(Mat4));
    return {};
}

void put_material(commit_pb::MaterialData* d, const Material& m) {
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
Status get_material(const commit_pb::MaterialData& d, Material& m) {
    m.name = d.name();
    m.metallic_factor = d.metallic_factor();
    m.roughness_factor = d.roughness_factor();
    m.normal_scale = d.normal_scale();
    m.emissive_strength = d.emissive_strength();
    m.transmission_factor = d.transmission_factor();
    m.ior = d.ior();
    m.specular_factor = d.specular_factor();
    m.attenuation_distance = d.attenuation_distance();
    m.double_sided = d.double_sided();
    m.alpha_cutoff = d.alpha_cutoff();
    m.alpha_mode = AlphaMode(d.alpha_mode());
    for (Status s :
         {check_enum(d.alpha_mode(), kAlphaModeCount, "alpha_mode"),
          get_ref(d.base_color_texture(), m.base_color_texture, "base_color_texture"),
          get_ref(d.metallic_roughness_texture(), m.metallic_roughness_texture,
                  "metallic_roughness_texture"),
          get_ref(d.normal_texture(), m.normal_texture, "normal_texture"),
          get_ref(d.emissive_texture(), m.emissive_texture, "emissive_texture"),
          get_floats<4>(d.base_color_factor(), &m.base_color_factor[0], "base_color_factor"),
          get_floats<3>(d.emissive_factor(), &m.emissive_factor[0], "emissive_factor"),
          get_floats<3>(d.specular_color_factor(), &m.specular_color_factor[0],
                        "specular_color_factor"),
          get_floats<3>(d.attenuation_color(), &m.attenuation_color[0], "attenuation_color")})
        if (!s) return s;
    return {};
}

commit_pb::MeshData mesh_data(const Mesh& m) {
    commit_pb::MeshData d;
    d.set_name(m.name);
    d.set_positions(to_bytes(m.positions));
    d.set_normals(to_bytes(m.normals));
    d.set_uvs(to_bytes(m.uvs));
    d.set_tangents(to_bytes(m.tangents));
    d.set_indices(to_bytes(m.indices));
    d.set_material(uint32_t(m.material));
    return d;
}
Status get_mesh(const commit_pb::MeshData& d, Mesh& m) {
    m.name = d.name();
    m.material = int(d.material());
    for (Status s :
         {from_bytes(d.positions(), m.positions, "positions"),
          from_bytes(d.normals(), m.normals, "normals"), from_bytes(d.uvs(), m.uvs, "uvs"),
          from_bytes(d.tangents(), m.tangents, "tangents"),
          from_bytes(d.indices(), m.indices, "indices")})
        if (!s) return s;
    if (m.indices.size() % 3 != 0)
        return make_error(ErrorCode::parse_error, "indices: {} values, not a multiple of 3",
                          m.indices.size());
    for (const auto& [name, count] :
         {std::pair{"normals", m.normals.size()}, std::pair{"uvs", m.uvs.size()},
          std::pair{"tangents", m.tangents.size()}})
        if (count != 0 && count != m.positions.size())
            return make_error(ErrorCode::parse_error, "{}: {} values for {} positions", name, count,
                              m.positions.size());
    return {};
}

commit_pb::ImageData image_data(const Image& image) {
    commit_pb::ImageData d;
    d.set_name(image.name);
    d.set_width(uint32_t(image.width));
    d.set_height(uint32_t(image.height));
    d.set_rgba(to_bytes(image.rgba));
    return d;
}
Status get_image(const commit_pb::ImageData& d, Image& image) {
    image = Image{d.name(), int(d.width()), int(d.height()), {}};
    return from_bytes(d.rgba(), image.rgba, "rgba");
}

void put_texture(commit_pb::TextureData* d, const Texture& t) {
    d->set_image(t.image);
    d->set_filter(uint32_t(t.sampler.filter));
    d->set_wrap_s(uint32_t(t.sampler.wrap_s));
    d->set_wrap_t(uint32_t(t.sampler.wrap_t));
}
Status get_texture(const commit_pb::TextureData& d, Texture& t) {
    for (Status s : {check_enum(d.filter(), kFilterModeCount, "filter"),
                     check_enum(d.wrap_s(), kWrapModeCount, "wrap_s"),
                     check_enum(d.wrap_t(), kWrapModeCount, "wrap_t")})
        if (!s) return s;
    t = Texture{d.image(),
                Sampler{FilterMode(d.filter()), WrapMode(d.wrap_s()), WrapMode(d.wrap_t())}};
    return {};
}

void put_camera(commit_pb::CameraData* d, const Camera& c) {
    d->set_name(c.name);
    d->set_camera_to_world(mat_bytes(c.camera_to_world));
    d->set_yfov_radians(c.yfov_radians);
}
Status get_camera(const commit_pb::CameraData& d, Camera& c) {
    c.name = d.name();
    c.yfov_radians = d.yfov_radians();
    return mat_from(d.camera_to_world(), c.camera_to_world, "camera_to_world");
}

void put_environment(commit_pb::EnvironmentData* d, const Environment& e) {
    d->set_sky(uint32_t(e.sky));
    put_floats(d->mutable_sun_direction(), &e.sun_direction[0], 3);
    d->set_turbidity(e.turbidity);
    d->set_sun_scale(e.sun_scale);
}
Status get_environment(const commit_pb::EnvironmentData& d, Environment& e) {
    if (Status s = check_enum(d.sky(), kSkyModeCount, "sky"); !s) return s;
    e.sky = SkyMode(d.sky());
    e.turbidity = d.turbidity();
    e.sun_scale = d.sun_scale();
    return get_floats<3>(d.sun_direction(), &e.sun_direction[0], "sun_direction");
}

void put_settings(commit_pb::SettingsData* d, const RenderSettings& s) {
    d->set_width(s.width);
    d->set_height(s.height);
    d->set_spp(s.spp);
    d->set_max_depth(s.max_depth);
    d->set_seed(s.seed);
}
RenderSettings get_settings(const commit_pb::SettingsData& d) {
    return RenderSettings{d.width(), d.height(), d.spp(), d.max_depth(), d.seed()};
}

}  // namespace pathfarm::codec
