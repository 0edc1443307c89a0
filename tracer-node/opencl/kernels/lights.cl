// Next-event estimation's light choice (common/render/light_sampler.cpp) and the Preetham
// sun/sky (common/render/sun_sky.cpp), from the parameters the host extracted.

typedef struct {
    float3 p;  // point on the light, or a direction (environment)
    float3 n;
    float3 radiance;
    float pdf;
    bool environment;
} PfLightSample;

float pf_perez(__global const float* c, float cos_theta, float gamma, float cos_gamma) {
    return (1.0f + c[0] * exp(c[1] / fmax(cos_theta, 0.01f))) *
           (1.0f + c[2] * exp(c[3] * gamma) + c[4] * cos_gamma * cos_gamma);
}

float3 pf_xyy_to_rgb(float x, float y, float luminance_y) {
    if (y <= 0.0f) return (float3)(0.0f);
    const float cx = x / y * luminance_y;
    const float cz = (1.0f - x - y) / y * luminance_y;
    return fmax((float3)(3.2406f * cx - 1.5372f * luminance_y - 0.4986f * cz,
                         -0.9689f * cx + 1.8758f * luminance_y + 0.0415f * cz,
                         0.0557f * cx - 0.2040f * luminance_y + 1.0570f * cz),
                (float3)(0.0f));
}

float3 pf_sky_radiance(__global const PfSceneGlobals* g, float3 w) {
    if (w.y <= 0.0f) return (float3)(0.0f);
    const float cos_gamma = clamp(dot(w, pf_vec3(g->sun_dir)), -1.0f, 1.0f);
    const float gamma = acos(cos_gamma);
    const float y = g->zenith_y * pf_perez(g->perez_y, w.y, gamma, cos_gamma) / g->perez_zenith_y;
    const float x = g->zenith_x * pf_perez(g->perez_x, w.y, gamma, cos_gamma) / g->perez_zenith_x;
    const float yy =
        g->zenith_yy * pf_perez(g->perez_yy, w.y, gamma, cos_gamma) / g->perez_zenith_yy;
    return pf_xyy_to_rgb(x, yy, fmax(y, 0.0f)) * g->sky_scale;
}

bool pf_in_sun(__global const PfSceneGlobals* g, float3 w) {
    return dot(w, pf_vec3(g->sun_dir)) >= g->sun_cos_max;
}

float3 pf_environment_radiance(__global const PfSceneGlobals* g, float3 w) {
    float3 l = pf_sky_radiance(g, w);
    if (pf_in_sun(g, w)) l += pf_vec3(g->sun_radiance);
    return l;
}

float pf_sun_sky_pdf(__global const PfSceneGlobals* g, float3 w) {
    float p = w.y > 0.0f ? (1.0f - g->p_sun) / (2.0f * PF_PI) : 0.0f;
    if (g->p_sun > 0.0f && pf_in_sun(g, w)) p += g->p_sun * pf_uniform_cone_pdf(g->sun_cos_max);
    return p;
}

// Selection probability times the sky's solid-angle density.
float pf_environment_pdf(__global const PfSceneGlobals* g, float3 w) {
    return g->has_environment ? g->p_environment * pf_sun_sky_pdf(g, w) : 0.0f;
}

bool pf_lights_empty(__global const PfSceneGlobals* g) {
    return g->light_count == 0 && g->has_environment == 0u;
}

// The light tree (common/render/light_tree.cpp, light_bounds.h): the same importance bound,
// descent and distant-node switch to power, so both backends choose emitters alike.
float pf_cos_subtract_clamped(float cos_a, float sin_a, float cos_b, float sin_b) {
    return cos_a >= cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}

float pf_light_importance(__global const PfLightNode* b, float3 p, float3 n) {
    if (!(b->power > 0.0f)) return 0.0f;
    const float3 to_p = p - pf_vec3(b->center);
    const float dist2 = dot(to_p, to_p);
    const float inv_dist = dist2 > 0.0f ? 1.0f / sqrt(dist2) : 0.0f;
    float cos_b = -1.0f, sin_b = 0.0f;
    if (dist2 > b->radius2) {
        const float sin2 = b->radius2 * inv_dist * inv_dist;
        sin_b = sqrt(sin2);
        cos_b = sqrt(fmax(0.0f, 1.0f - sin2));
    }
    float cos_w = dot(pf_vec3(b->axis), to_p) * inv_dist;
    if ((b->flags & PF_LIGHT_TWO_SIDED) != 0u) cos_w = fabs(cos_w);
    float cos_wo = 1.0f, sin_wo = 0.0f;
    if (cos_w < b->cos_theta_o) {
        const float sin_w = sqrt(fmax(0.0f, 1.0f - cos_w * cos_w));
        cos_wo = cos_w * b->cos_theta_o + sin_w * b->sin_theta_o;
        sin_wo = fmax(0.0f, sin_w * b->cos_theta_o - cos_w * b->sin_theta_o);
    }
    const float cos_x = pf_cos_subtract_clamped(cos_wo, sin_wo, cos_b, sin_b);
    if (!(cos_x > 0.0f)) return 0.0f;
    float result = b->power * cos_x / fmax(fmax(dist2, b->radius2), 1e-20f);
    if (n.x != 0.0f || n.y != 0.0f || n.z != 0.0f) {
        const float cos_i = fabs(dot(to_p, n)) * inv_dist;
        if (cos_i < cos_b) result *= cos_i * cos_b + sqrt(fmax(0.0f, 1.0f - cos_i * cos_i)) * sin_b;
    }
    return isfinite(result) ? result : 0.0f;
}

bool pf_light_distant(__global const PfLightNode* b, float3 p) {
    const float3 d = p - pf_vec3(b->center);
    return b->radius2 < PF_LIGHT_DISTANT_SIN2 * dot(d, d) && b->cos_theta_o > PF_LIGHT_DISTANT_COS;
}

// LightTree::first_child_probability.
float pf_first_child_probability(const PfScene* s, uint i, float3 p, float3 n, bool* by_power) {
    __global const PfLightNode* a = &s->light_nodes[i + 1];
    __global const PfLightNode* b = &s->light_nodes[s->light_nodes[i].child_or_emitter];
    if (!*by_power) {
        const float i0 = pf_light_importance(a, p, n), i1 = pf_light_importance(b, p, n);
        if (i0 + i1 > 0.0f) return i0 / (i0 + i1);
        *by_power = true;
    }
    return a->power + b->power > 0.0f ? a->power / (a->power + b->power) : -1.0f;
}

bool pf_light_tree_sample(const PfScene* s, float3 p, float3 n, float u, uint* emitter,
                          float* pmf_out) {
    uint i = 0;
    float pmf = 1.0f;
    bool by_power = (s->light_nodes[0].flags & PF_LIGHT_LEAF) != 0u ||
                    pf_light_distant(&s->light_nodes[0], p);
    while ((s->light_nodes[i].flags & PF_LIGHT_LEAF) == 0u) {
        const float p0 = pf_first_child_probability(s, i, p, n, &by_power);
        if (p0 < 0.0f) return false;
        if (u < p0) {
            i = i + 1;
            pmf *= p0;
            u = fmin(u / p0, 0x1.fffffep-1f);
        } else {
            i = s->light_nodes[i].child_or_emitter;
            pmf *= 1.0f - p0;
            u = fmin((u - p0) / (1.0f - p0), 0x1.fffffep-1f);
        }
        by_power = by_power || pf_light_distant(&s->light_nodes[i], p);
    }
    uint k = s->light_nodes[i].child_or_emitter;
    if ((s->light_nodes[i].flags & PF_LIGHT_PAIR) != 0u && !(u < s->lights[k].tree_share)) ++k;
    *emitter = k;
    *pmf_out = pmf * s->lights[k].tree_share;
    return true;
}

float pf_light_tree_pmf(const PfScene* s, float3 p, float3 n, uint emitter) {
    __global const PfLight* light = &s->lights[emitter];
    uint i = 0;
    float pmf = light->tree_share;
    bool by_power = (s->light_nodes[0].flags & PF_LIGHT_LEAF) != 0u ||
                    pf_light_distant(&s->light_nodes[0], p);
    for (uint d = 0; (s->light_nodes[i].flags & PF_LIGHT_LEAF) == 0u; ++d) {
        const float p0 = pf_first_child_probability(s, i, p, n, &by_power);
        if (p0 < 0.0f) return 0.0f;
        const uint bit = d < 32u ? (light->trail_lo >> d) & 1u : (light->trail_hi >> (d - 32u)) & 1u;
        pmf *= bit != 0u ? 1.0f - p0 : p0;
        i = bit != 0u ? s->light_nodes[i].child_or_emitter : i + 1;
        by_power = by_power || pf_light_distant(&s->light_nodes[i], p);
    }
    return pmf;
}

bool pf_sample_light(const PfScene* s, float3 from, float3 normal, float u_select, float2 u,
                     PfLightSample* ls) {
    __global const PfSceneGlobals* g = s->globals;
    if (pf_lights_empty(g)) return false;
    ls->n = (float3)(0.0f);
    ls->environment = false;
    if (u_select < g->p_environment) {
        const float u_choice = u_select / g->p_environment;
        float3 wi;
        if (u_choice < g->p_sun) {
            const PfFrame f = pf_frame_from_normal(pf_vec3(g->sun_dir));
            wi = pf_to_world(&f, pf_sample_uniform_cone(u, g->sun_cos_max));
        } else {
            const float3 h = pf_sample_uniform_sphere((float2)(0.5f * u.x, u.y));
            wi = (float3)(h.x, h.z, h.y);
        }
        const float pdf = pf_sun_sky_pdf(g, wi);
        if (pdf <= 0.0f) return false;
        ls->p = wi;
        ls->radiance = pf_environment_radiance(g, wi);
        ls->pdf = g->p_environment * pdf;
        ls->environment = true;
        return true;
    }
    const float us = (u_select - g->p_environment) / (1.0f - g->p_environment);
    uint k;
    float pmf;
    if (g->light_tree != 0u) {
        if (!pf_light_tree_sample(s, from, normal, us, &k, &pmf)) return false;
    } else {
        // upper_bound: the first light whose cumulative power exceeds us.
        uint lo = 0, hi = g->light_count;
        while (lo < hi) {
            const uint mid = (lo + hi) / 2;
            if (s->lights[mid].cdf <= us) lo = mid + 1;
            else hi = mid;
        }
        k = min(lo, g->light_count - 1);
        pmf = s->lights[k].cdf - (k > 0 ? s->lights[k - 1].cdf : 0.0f);
    }
    __global const PfLight* tri = &s->lights[k];
    if (tri->area <= 0.0f) return false;
    const float2 b = pf_sample_uniform_triangle(u);
    ls->p = pf_vec3(tri->p0) + b.x * pf_vec3(tri->e1) + b.y * pf_vec3(tri->e2);
    ls->n = pf_vec3(tri->n);
    ls->pdf = (1.0f - g->p_environment) * pmf / tri->area;
    __global const PfMaterial* mat = &s->materials[tri->material];
    const bool alpha_tested = (s->meshes[s->instances[tri->instance].mesh].flags &
                               PF_MESH_ALPHA_TESTED) != 0u;
    if (mat->emissive_texture >= 0 || alpha_tested) {  // needs the UV: rebuild the surface point
        PfSurface sp = pf_surface(s, tri->instance, tri->prim, b.x, b.y);
        sp.p = ls->p;
        ls->radiance = pf_emitted(s, &sp, normalize(from - ls->p));
        // light_sampler.cpp: a ray meets a cut-out or blended emitter only where it is there.
        if (alpha_tested) ls->radiance *= pf_alpha_coverage(mat, pf_base_color_alpha(s, mat, sp.uv));
    } else {
        const bool front = dot(from - ls->p, ls->n) > 0.0f;
        ls->radiance = front || mat->double_sided ? pf_vec3(mat->emission) : (float3)(0.0f);
    }
    return true;
}

// Selection probability (for a receiver at `from` with normal `normal`) times 1/area for the
// emissive triangle, 0 if it is not a light.
float pf_triangle_pdf_area(const PfScene* s, uint instance, uint prim, float3 from,
                           float3 normal) {
    const int first = s->instances[instance].first_light;
    if (first < 0) return 0.0f;
    const uint k = (uint)first + prim;
    __global const PfLight* tri = &s->lights[k];
    const float pmf = s->globals->light_tree != 0u
                          ? pf_light_tree_pmf(s, from, normal, k)
                          : tri->cdf - (k > 0 ? s->lights[k - 1].cdf : 0.0f);
    return tri->area > 0.0f ? (1.0f - s->globals->p_environment) * pmf / tri->area : 0.0f;
}
