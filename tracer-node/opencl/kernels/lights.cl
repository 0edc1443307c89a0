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

bool pf_sample_light(const PfScene* s, float3 from, float u_select, float2 u, PfLightSample* ls) {
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
    // upper_bound: the first light whose cumulative power exceeds us.
    uint lo = 0, hi = g->light_count;
    while (lo < hi) {
        const uint mid = (lo + hi) / 2;
        if (s->lights[mid].cdf <= us) lo = mid + 1;
        else hi = mid;
    }
    const uint k = min(lo, g->light_count - 1);
    __global const PfLight* tri = &s->lights[k];
    if (tri->area <= 0.0f) return false;
    const float2 b = pf_sample_uniform_triangle(u);
    ls->p = pf_vec3(tri->p0) + b.x * pf_vec3(tri->e1) + b.y * pf_vec3(tri->e2);
    ls->n = pf_vec3(tri->n);
    const float pmf = tri->cdf - (k > 0 ? s->lights[k - 1].cdf : 0.0f);
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

// Selection probability times 1/area for the emissive triangle, 0 if it is not a light.
float pf_triangle_pdf_area(const PfScene* s, uint instance, uint prim) {
    const int first = s->instances[instance].first_light;
    if (first < 0) return 0.0f;
    const uint k = (uint)first + prim;
    __global const PfLight* tri = &s->lights[k];
    const float pmf = tri->cdf - (k > 0 ? s->lights[k - 1].cdf : 0.0f);
    return tri->area > 0.0f ? (1.0f - s->globals->p_environment) * pmf / tri->area : 0.0f;
}
