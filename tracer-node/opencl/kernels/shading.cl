// Surfaces, textures and materials: common/render/shading_scene.cpp and
// common/scene/texture.cpp on the device.

typedef struct {
    float3 p;
    float3 ng;  // unit geometric normal of the front face
    float3 ns;  // unit shading normal, on ng's side
    float3 tangent;
    float bitangent_sign;
    float2 uv;
    float uv_density;  // SurfacePoint::uv_density
    int material;
} PfSurface;

typedef struct {
    float3 base_color;
    float metallic;
    float alpha;
    float transmission;
    float ior;
    float specular;
    float3 specular_color;
} PfMaterialPoint;

// Orthonormal frame (common/math/frame.h).
typedef struct {
    float3 t, b, n;
} PfFrame;

PfFrame pf_frame_from_normal(float3 n) {
    const float sign = copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    PfFrame f;
    f.t = (float3)(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    f.b = (float3)(c, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

PfFrame pf_frame_from_normal_tangent(float3 n, float3 t_hint) {
    float3 t = t_hint - n * dot(n, t_hint);
    const float len2 = dot(t, t);
    if (!(len2 > 1e-12f)) return pf_frame_from_normal(n);
    t *= 1.0f / sqrt(len2);
    PfFrame f;
    f.t = t;
    f.b = cross(n, t);
    f.n = n;
    return f;
}

float3 pf_to_local(const PfFrame* f, float3 v) {
    return (float3)(dot(v, f->t), dot(v, f->b), dot(v, f->n));
}
float3 pf_to_world(const PfFrame* f, float3 v) { return f->t * v.x + f->b * v.y + f->n * v.z; }

float3 pf_normalize_or(float3 v, float3 fallback) {
    const float len2 = dot(v, v);
    return len2 > 1e-20f && isfinite(len2) ? v / sqrt(len2) : fallback;
}

int pf_wrap_index(int i, int n, uint mode) {
    if (mode == PF_WRAP_CLAMP_TO_EDGE) return clamp(i, 0, n - 1);
    if (mode == PF_WRAP_MIRRORED_REPEAT) {
        const int period = 2 * n;
        int m = i % period;
        if (m < 0) m += period;
        return m < n ? m : period - 1 - m;
    }
    int m = i % n;
    return m < 0 ? m + n : m;
}

// One level of a texture's image: where its texels start and its size.
typedef struct {
    uint first_texel;
    int width, height;
} PfImageLevel;

float4 pf_texel(const PfScene* s, PfImageLevel im, int x, int y, bool srgb) {
    __global const uchar* p =
        s->texels + 4 * ((size_t)im.first_texel + (size_t)y * (size_t)im.width + (size_t)x);
    const float4 v = (float4)(p[0], p[1], p[2], p[3]) * (1.0f / 255.0f);
    if (!srgb) return v;
    __global const float* table = s->globals->srgb_to_linear;
    return (float4)(table[p[0]], table[p[1]], table[p[2]], v.w);
}

// KHR_texture_transform (device_types.h: the affine map of a texture use).
float2 pf_uv(__global const float* m, float2 uv) {
    return (float2)(m[0] * uv.x + m[1] * uv.y + m[2], m[3] * uv.x + m[4] * uv.y + m[5]);
}

// mip_level (texture_mips.cpp).
int pf_mip_level(float texels, int max_level) {
    if (!(texels >= 4.0f) || max_level <= 0) return 0;
    if (texels > 1e30f) return max_level;
    return min(max_level, ilogb(texels) / 2);
}

// ShadingScene::texture_level: the level a footprint (world area, 0 at the camera's hit) of
// a surface with uv_density reads through the texture use's affine uv map m.
PfImageLevel pf_texture_level(__global const PfTexture* tex, __global const float* m,
                              float footprint, float uv_density) {
    PfImageLevel im = {tex->first_texel, tex->width, tex->height};
    if (footprint <= 0.0f || tex->levels == 0 || im.width <= 0) return im;
    const float texels = footprint * uv_density * fabs(m[0] * m[4] - m[1] * m[3]) *
                         (float)im.width * (float)im.height;
    const int level = pf_mip_level(texels, (int)tex->levels);
    for (int l = 0; l < level; ++l) {
        im.first_texel += (uint)im.width * (uint)im.height;
        im.width = max(1, im.width / 2);
        im.height = max(1, im.height / 2);
    }
    return im;
}

// sample_image: glTF wrap modes, nearest or bilinear, on one level of the image.
float4 pf_sample_level(const PfScene* s, __global const PfTexture* tex, PfImageLevel im,
                       float2 uv, bool srgb) {
    const int w = im.width, h = im.height;
    if (w <= 0 || h <= 0 || !isfinite(uv.x) || !isfinite(uv.y)) return (float4)(1.0f);
    const float fx = clamp(uv.x * (float)w, -1e7f, 1e7f);
    const float fy = clamp(uv.y * (float)h, -1e7f, 1e7f);
    if (tex->filter == PF_FILTER_NEAREST) {
        const int x = pf_wrap_index((int)floor(fx), w, tex->wrap_s);
        const int y = pf_wrap_index((int)floor(fy), h, tex->wrap_t);
        return pf_texel(s, im, x, y, srgb);
    }
    const float px = fx - 0.5f, py = fy - 0.5f;
    const int x0 = (int)floor(px), y0 = (int)floor(py);
    const float tx = px - (float)x0, ty = py - (float)y0;
    const int xa = pf_wrap_index(x0, w, tex->wrap_s), xb = pf_wrap_index(x0 + 1, w, tex->wrap_s);
    const int ya = pf_wrap_index(y0, h, tex->wrap_t), yb = pf_wrap_index(y0 + 1, h, tex->wrap_t);
    const float4 top = mix(pf_texel(s, im, xa, ya, srgb), pf_texel(s, im, xb, ya, srgb), tx);
    const float4 bottom = mix(pf_texel(s, im, xa, yb, srgb), pf_texel(s, im, xb, yb, srgb), tx);
    return mix(top, bottom, ty);
}

// A texture use (its affine uv map m) at a surface point, at the level its footprint asks for.
float4 pf_sample_texture_lod(const PfScene* s, int texture, __global const float* m, float2 uv,
                             bool srgb, float footprint, float uv_density) {
    __global const PfTexture* tex = &s->textures[texture];
    return pf_sample_level(s, tex, pf_texture_level(tex, m, footprint, uv_density), pf_uv(m, uv),
                           srgb);
}

// Level 0.
float4 pf_sample_texture(const PfScene* s, int texture, float2 uv, bool srgb) {
    __global const PfTexture* tex = &s->textures[texture];
    const PfImageLevel im = {tex->first_texel, tex->width, tex->height};
    return pf_sample_level(s, tex, im, uv, srgb);
}

void pf_triangle_vertices(const PfScene* s, uint instance, uint prim, float3 p[3]) {
    __global const PfInstance* inst = &s->instances[instance];
    __global const PfMesh* mesh = &s->meshes[inst->mesh];
    __global const uint* idx = s->indices + mesh->first_index + 3 * prim;
    for (int k = 0; k < 3; ++k)
        p[k] = pf_xform_point(inst->object_to_world,
                              pf_load3(s->positions + 3 * ((size_t)mesh->first_vertex + idx[k])));
}

PfSurface pf_surface(const PfScene* s, uint instance, uint prim, float u, float v) {
    __global const PfInstance* inst = &s->instances[instance];
    __global const PfMesh* mesh = &s->meshes[inst->mesh];
    __global const uint* idx = s->indices + mesh->first_index + 3 * prim;
    const size_t i0 = mesh->first_vertex + idx[0], i1 = mesh->first_vertex + idx[1],
                 i2 = mesh->first_vertex + idx[2];
    float3 p[3];
    pf_triangle_vertices(s, instance, prim, p);
    const float b0 = 1.0f - u - v;
    PfSurface sp;
    sp.material = mesh->material;
    sp.p = b0 * p[0] + u * p[1] + v * p[2];
    const float3 normal = cross(p[1] - p[0], p[2] - p[0]);
    sp.ng = pf_normalize_or(normal * inst->handedness, (float3)(0.0f, 0.0f, 1.0f));
    sp.ns = sp.ng;
    sp.tangent = (float3)(0.0f);
    sp.bitangent_sign = 1.0f;
    sp.uv = (float2)(0.0f);
    sp.uv_density = 0.0f;
    if (mesh->flags & PF_MESH_NORMALS) {
        const float3 n = b0 * pf_load3(s->normals + 3 * i0) + u * pf_load3(s->normals + 3 * i1) +
                         v * pf_load3(s->normals + 3 * i2);
        sp.ns = pf_normalize_or(pf_mul3x3(inst->normal_matrix, n), sp.ng);
        if (dot(sp.ns, sp.ng) < 0.0f) sp.ns = -sp.ns;
    }
    if (mesh->flags & PF_MESH_UVS) {
        const float2 t0 = vload2(i0, s->uvs), t1 = vload2(i1, s->uvs), t2 = vload2(i2, s->uvs);
        sp.uv = b0 * t0 + u * t1 + v * t2;
        const float2 e1 = t1 - t0, e2 = t2 - t0;  // both areas doubled: the ratio is the triangle's
        const float density = fabs(e1.x * e2.y - e1.y * e2.x) / length(normal);
        sp.uv_density = isfinite(density) ? density : 0.0f;
    }
    if (mesh->flags & PF_MESH_TANGENTS) {
        const float4 t =
            b0 * vload4(i0, s->tangents) + u * vload4(i1, s->tangents) + v * vload4(i2, s->tangents);
        sp.tangent = pf_xform_vector(inst->object_to_world, t.xyz);
        sp.bitangent_sign = (t.w < 0.0f ? -1.0f : 1.0f) * inst->handedness;
    }
    return sp;
}

// common/scene/alpha.h: the base colour's alpha and whether a candidate hit is kept.
float pf_base_color_alpha(const PfScene* s, __global const PfMaterial* m, float2 uv) {
    float a = m->base_color[3];
    if (m->base_color_texture >= 0)
        a *= pf_sample_texture(s, m->base_color_texture, pf_uv(m->base_color_uv, uv), true).w;
    return a;
}

float pf_alpha_coverage(__global const PfMaterial* m, float alpha) {
    if (m->alpha_mode == PF_ALPHA_MASK) return alpha >= m->alpha_cutoff ? 1.0f : 0.0f;
    if (m->alpha_mode == PF_ALPHA_BLEND) return clamp(alpha, 0.0f, 1.0f);
    return 1.0f;
}

// alpha_hash: hash_words over the ray, the candidate distance and the primitive.
float pf_alpha_hash(float3 o, float3 d, float t, uint prim) {
    const uint w[8] = {as_uint(o.x), as_uint(o.y), as_uint(o.z), as_uint(d.x),
                       as_uint(d.y), as_uint(d.z), as_uint(t),   prim};
    uint h = PF_HASH_WORDS_START;
    for (int k = 0; k < 8; ++k)
        h = pf_hash_fold(h, w[k]);
    return (float)(h >> 8) * 0x1p-24f;
}

bool pf_alpha_keeps_hit(const PfScene* s, __global const PfMesh* mesh, uint prim, float u, float v,
                        float3 o, float3 d, float t) {
    __global const PfMaterial* m = &s->materials[mesh->material];
    float2 uv = (float2)(0.0f);
    if (mesh->flags & PF_MESH_UVS) {
        __global const uint* idx = s->indices + mesh->first_index + 3 * prim;
        const uint base = mesh->first_vertex;
        uv = (1.0f - u - v) * vload2(base + idx[0], s->uvs) + u * vload2(base + idx[1], s->uvs) +
             v * vload2(base + idx[2], s->uvs);
    }
    const float alpha = pf_base_color_alpha(s, m, uv);
    if (m->alpha_mode == PF_ALPHA_MASK) return alpha >= m->alpha_cutoff;
    if (m->alpha_mode == PF_ALPHA_BLEND) return pf_alpha_hash(o, d, t, prim) < alpha;
    return true;
}

// ShadingScene::material_point; footprint: the path's ray cone at sp (0 at the camera's hit).
PfMaterialPoint pf_material_point(const PfScene* s, PfSurface* sp, float footprint) {
    __global const PfMaterial* m = &s->materials[sp->material];
    PfMaterialPoint mp;
    float4 base = vload4(0, m->base_color);
    const float density = sp->uv_density;
    if (m->base_color_texture >= 0)
        base *= pf_sample_texture_lod(s, m->base_color_texture, m->base_color_uv, sp->uv, true,
                                      footprint, density);
    mp.base_color = clamp(base.xyz, 0.0f, 1.0f);
    float roughness = m->roughness, metallic = m->metallic;
    if (m->metallic_roughness_texture >= 0) {
        const float4 mr = pf_sample_texture_lod(s, m->metallic_roughness_texture,
                                                m->metallic_roughness_uv, sp->uv, false,
                                                footprint, density);
        roughness *= mr.y;
        metallic *= mr.z;
    }
    roughness = clamp(isfinite(roughness) ? roughness : 1.0f, 0.0f, 1.0f);
    mp.alpha = roughness * roughness;
    mp.metallic = clamp(isfinite(metallic) ? metallic : 0.0f, 0.0f, 1.0f);
    mp.transmission = m->transmission;
    mp.ior = m->ior;
    mp.specular = m->specular;
    mp.specular_color = pf_vec3(m->specular_color);
    if (m->normal_texture >= 0 && dot(sp->tangent, sp->tangent) > 0.0f) {
        const float4 t = pf_sample_texture_lod(s, m->normal_texture, m->normal_uv, sp->uv, false,
                                               footprint, density);
        float3 tn = t.xyz * 2.0f - (float3)(1.0f);
        tn.x *= m->normal_scale;
        tn.y *= m->normal_scale;
        const PfFrame f = pf_frame_from_normal_tangent(sp->ns, sp->tangent);
        const float3 n =
            pf_normalize_or(f.t * tn.x + f.b * (tn.y * sp->bitangent_sign) + sp->ns * tn.z, sp->ns);
        if (dot(n, sp->ng) > 0.0f) sp->ns = n;
    }
    return mp;
}

// Radiance emitted at sp towards wo (front face only unless double-sided).
float3 pf_emitted(const PfScene* s, const PfSurface* sp, float3 wo) {
    __global const PfMaterial* m = &s->materials[sp->material];
    if (m->emissive == 0u) return (float3)(0.0f);
    if (m->double_sided == 0u && dot(wo, sp->ng) <= 0.0f) return (float3)(0.0f);
    float3 le = pf_vec3(m->emission);
    if (m->emissive_texture >= 0)
        le *= pf_sample_texture(s, m->emissive_texture, pf_uv(m->emissive_uv, sp->uv), true).xyz;
    return le;
}
