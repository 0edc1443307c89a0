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

// The light tree (common/render/light_tree.cpp, light_bounds.h): the same importance bound and
// estimate per slot of a wide node, their mean, descent and distant-node switch to power, so
// both backends choose emitters alike.
float pf_cos_subtract_clamped(float cos_a, float sin_a, float cos_b, float sin_b) {
    return cos_a >= cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}

float pf_light_importance(__global const PfLightNode* b, int k, float3 p, float3 n) {
    const float power = b->power[k];
    if (!(power > 0.0f)) return 0.0f;
    const float radius2 = b->radius2[k];
    const float3 to_p = p - (float3)(b->center[0][k], b->center[1][k], b->center[2][k]);
    const float dist2 = dot(to_p, to_p);
    const float inv_dist = dist2 > 0.0f ? 1.0f / sqrt(dist2) : 0.0f;
    float cos_b = -1.0f, sin_b = 0.0f;
    if (dist2 > radius2) {
        const float sin2 = radius2 * inv_dist * inv_dist;
        sin_b = sqrt(sin2);
        cos_b = sqrt(fmax(0.0f, 1.0f - sin2));
    }
    float cos_w = dot((float3)(b->axis[0][k], b->axis[1][k], b->axis[2][k]), to_p) * inv_dist;
    if ((b->flags[k] & PF_LIGHT_TWO_SIDED) != 0u) cos_w = fabs(cos_w);
    const float cos_o = b->cos_theta_o[k], sin_o = b->sin_theta_o[k];
    float cos_wo = 1.0f, sin_wo = 0.0f;
    if (cos_w < cos_o) {
        const float sin_w = sqrt(fmax(0.0f, 1.0f - cos_w * cos_w));
        cos_wo = cos_w * cos_o + sin_w * sin_o;
        sin_wo = fmax(0.0f, sin_w * cos_o - cos_w * sin_o);
    }
    const float cos_x = pf_cos_subtract_clamped(cos_wo, sin_wo, cos_b, sin_b);
    if (!(cos_x > 0.0f)) return 0.0f;
    float result = power * cos_x / fmax(fmax(dist2, 0.25f * radius2), 1e-20f);
    if (n.x != 0.0f || n.y != 0.0f || n.z != 0.0f) {
        const float cos_i = fabs(dot(to_p, n)) * inv_dist;
        if (cos_i < cos_b) result *= cos_i * cos_b + sqrt(fmax(0.0f, 1.0f - cos_i * cos_i)) * sin_b;
    }
    return isfinite(result) ? result : 0.0f;
}

// estimate() (light_bounds.h) of slot k, zero where its importance is.
float pf_light_estimate(__global const PfLightNode* b, int k, float3 p, float3 n,
                        float importance) {
    if (!(importance > 0.0f)) return 0.0f;
    const float3 to_p = p - (float3)(b->center[0][k], b->center[1][k], b->center[2][k]);
    const float dist2 = dot(to_p, to_p);
    const float inv_dist = dist2 > 0.0f ? 1.0f / sqrt(dist2) : 0.0f;
    const float one_sided =
        dot((float3)(b->mean_normal[0][k], b->mean_normal[1][k], b->mean_normal[2][k]), to_p) *
        inv_dist;
    const bool single = (b->flags[k] & (PF_LIGHT_LEAF | PF_LIGHT_PAIR)) == PF_LIGHT_LEAF;
    const float spread =
        single ? 2.0f * fabs(dot((float3)(b->axis[0][k], b->axis[1][k], b->axis[2][k]), to_p)) *
                     inv_dist
               : 1.0f;
    float result = b->power[k] * (fmax(0.0f, one_sided) + b->diffuse_share[k] * spread) /
                   fmax(fmax(dist2, 0.25f * b->radius2[k]), 1e-20f);
    if (n.x != 0.0f || n.y != 0.0f || n.z != 0.0f) result *= fabs(dot(to_p, n)) * inv_dist;
    return isfinite(result) ? result : 0.0f;
}

bool pf_light_distant(float3 center, float radius2, float cos_theta_o, float3 p) {
    const float3 d = p - center;
    return radius2 < PF_LIGHT_DISTANT_SIN2 * dot(d, d) && cos_theta_o > PF_LIGHT_DISTANT_COS;
}

bool pf_light_slot_distant(__global const PfLightNode* b, int k, float3 p) {
    return pf_light_distant((float3)(b->center[0][k], b->center[1][k], b->center[2][k]),
                            b->radius2[k], b->cos_theta_o[k], p);
}

bool pf_light_root_by_power(__global const PfSceneGlobals* g, float3 p) {
    return g->light_root_leaf != 0u ||
           pf_light_distant(pf_vec3(g->light_root_center), g->light_root_radius2,
                            g->light_root_cos_theta_o, p);
}

// LightTree::slot_weights.
float pf_slot_weights(__global const PfLightNode* b, float3 p, float3 n, bool* by_power,
                      float* weight) {
    if (!*by_power) {
        for (int k = 0; k < 4; ++k)
            weight[k] = pf_light_importance(b, k, p, n);
        const float total = (weight[0] + weight[1]) + (weight[2] + weight[3]);
        if (total > 0.0f) {
            float guess[4];
            for (int k = 0; k < 4; ++k)
                guess[k] = pf_light_estimate(b, k, p, n, weight[k]);
            const float guessed = (guess[0] + guess[1]) + (guess[2] + guess[3]);
            if (!(guessed > 0.0f)) return total;
            const float a = 0.5f / total, c = 0.5f / guessed;
            for (int k = 0; k < 4; ++k)
                weight[k] = a * weight[k] + c * guess[k];
            return (weight[0] + weight[1]) + (weight[2] + weight[3]);
        }
        *by_power = true;
    }
    for (int k = 0; k < 4; ++k)
        weight[k] = fmax(0.0f, b->power[k]);
    return (weight[0] + weight[1]) + (weight[2] + weight[3]);
}

bool pf_light_tree_sample(const PfScene* s, float3 p, float3 n, float u, uint* emitter,
                          float* pmf_out) {
    bool by_power = pf_light_root_by_power(s->globals, p);
    float pmf = 1.0f;
    for (uint node = 0;;) {
        __global const PfLightNode* b = &s->light_nodes[node];
        float weight[4];
        const float total = pf_slot_weights(b, p, n, &by_power, weight);
        if (!(total > 0.0f)) return false;
        const float target = u * total;
        int slot = -1;
        float below = 0.0f, lower = 0.0f;
        for (int k = 0; k < 4; ++k) {
            if (!(weight[k] > 0.0f)) continue;
            slot = k;
            lower = below;
            below += weight[k];
            if (target < below) break;
        }
        pmf *= weight[slot] / total;
        u = clamp((target - lower) / weight[slot], 0.0f, 0x1.fffffep-1f);
        if ((b->flags[slot] & PF_LIGHT_LEAF) != 0u) {
            uint k = b->child[slot];
            if ((b->flags[slot] & PF_LIGHT_PAIR) != 0u && !(u < s->lights[k].tree_share)) ++k;
            *emitter = k;
            *pmf_out = pmf * s->lights[k].tree_share;
            return true;
        }
        by_power = by_power || pf_light_slot_distant(b, slot, p);
        node = b->child[slot];
    }
}

float pf_light_tree_pmf(const PfScene* s, float3 p, float3 n, uint emitter) {
    __global const PfLight* light = &s->lights[emitter];
    bool by_power = pf_light_root_by_power(s->globals, p);
    float pmf = light->tree_share;
    for (uint node = 0, d = 0;; ++d) {
        __global const PfLightNode* b = &s->light_nodes[node];
        float weight[4];
        const float total = pf_slot_weights(b, p, n, &by_power, weight);
        if (!(total > 0.0f)) return 0.0f;
        const uint shift = 2u * d;
        const int slot = (int)((shift < 32u ? light->trail_lo >> shift
                                            : light->trail_hi >> (shift - 32u)) & 3u);
        if (!(weight[slot] > 0.0f)) return 0.0f;
        pmf *= weight[slot] / total;
        if ((b->flags[slot] & PF_LIGHT_LEAF) != 0u) return pmf;
        by_power = by_power || pf_light_slot_distant(b, slot, p);
        node = b->child[slot];
    }
}

// std::upper_bound over the lights' cdf in [lo, hi): the first light whose cumulative power
// exceeds u.
uint pf_cdf_upper_bound(const PfScene* s, uint lo, uint hi, float u) {
    while (lo < hi) {
        const uint mid = (lo + hi) / 2;
        if (s->lights[mid].cdf <= u) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

// GuidedCdf::upper_bound (common/sampling/guided_cdf.h): the search narrowed by the guide
// table to u's bucket, the answer checked against its neighbours and searched for over the
// whole cdf where rounding put u in the wrong bucket, so it is the whole search's to the bit.
uint pf_light_upper_bound(const PfScene* s, uint m, float u) {
    const float scaled = u * (float)m;
    if (scaled >= 0.0f && scaled < (float)m) {
        const uint j = (uint)scaled;
        const uint k = pf_cdf_upper_bound(s, s->light_guide[j], s->light_guide[j + 1], u);
        if ((k == 0 || !(s->lights[k - 1].cdf > u)) && (k == m || s->lights[k].cdf > u)) return k;
    }
    return pf_cdf_upper_bound(s, 0, m, u);
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
        k = min(pf_light_upper_bound(s, g->light_count, us), g->light_count - 1);
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
