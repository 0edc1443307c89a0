// The scene on the device, small vector helpers, and ray traversal of the two-level BVH:
// a top level over instances, then each instance's mesh BVH (the coordinator's layout,
// common/scene/bvh_node.h) in object space.

#define PF_INFINITY INFINITY
#define PF_PI 3.14159265358979323846f
#define PF_INV_PI 0.31830988618379067154f
#define PF_STACK_SIZE 64

// The scene's arrays (device_types.h PF_SCENE_ARRAYS) and globals, as the kernel received them.
#define PF_SCENE_FIELD(name, type) __global const type* name;
typedef struct {
    PF_SCENE_ARRAYS(PF_SCENE_FIELD)
    __global const PfSceneGlobals* globals;
} PfScene;

typedef struct {
    float3 o;
    float3 d;
    float tmax;
} PfRay;

typedef struct {
    float t;
    uint instance;
    uint prim;
    float u;
    float v;
} PfHit;

float pf_max3(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }
float pf_luminance(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
float pf_safe_sqrt(float x) { return sqrt(fmax(0.0f, x)); }
float pf_sqr(float x) { return x * x; }
float3 pf_load3(__global const float* p) { return (float3)(p[0], p[1], p[2]); }
float3 pf_vec3(__global const float* p) { return (float3)(p[0], p[1], p[2]); }
bool pf_is_finite3(float3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

float3 pf_xform_point(__global const float* m, float3 p) {
    return (float3)(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
                    m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                    m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}
float3 pf_xform_vector(__global const float* m, float3 v) {
    return (float3)(m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
                    m[8] * v.x + m[9] * v.y + m[10] * v.z);
}
float3 pf_mul3x3(__global const float* m, float3 v) {
    return (float3)(m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
                    m[6] * v.x + m[7] * v.y + m[8] * v.z);
}

// common/math/float_util.h offset_ray_origin: integer steps away from the surface, scaled to
// the magnitude of each coordinate (Wächter & Binder, Ray Tracing Gems ch. 6).
float3 pf_offset_ray_origin(float3 p, float3 n) {
    const float origin = 1.0f / 32.0f, float_scale = 1.0f / 65536.0f, int_scale = 256.0f;
    const int3 of_i = (int3)((int)(int_scale * n.x), (int)(int_scale * n.y), (int)(int_scale * n.z));
    const float3 p_i = (float3)(as_float(as_int(p.x) + (p.x < 0.0f ? -of_i.x : of_i.x)),
                                as_float(as_int(p.y) + (p.y < 0.0f ? -of_i.y : of_i.y)),
                                as_float(as_int(p.z) + (p.z < 0.0f ? -of_i.z : of_i.z)));
    return (float3)(fabs(p.x) < origin ? p.x + float_scale * n.x : p_i.x,
                    fabs(p.y) < origin ? p.y + float_scale * n.y : p_i.y,
                    fabs(p.z) < origin ? p.z + float_scale * n.z : p_i.z);
}

// common/math/float_util.h shadow_ray_between: the segment between the two offset points.
PfRay pf_shadow_ray_between(float3 from, float3 from_n, float3 to, float3 to_n) {
    PfRay r;
    r.o = pf_offset_ray_origin(from, from_n);
    const float3 d = pf_offset_ray_origin(to, to_n) - r.o;
    const float len = sqrt(dot(d, d));
    r.d = len > 0.0f ? d / len : (float3)(0.0f, 0.0f, 1.0f);
    r.tmax = len * (1.0f - 1e-5f);
    return r;
}

// Slab test; returns the entry distance or INFINITY on a miss.
float pf_box_entry(__global const PfBvhNode* node, float3 o, float3 inv_d, float tmax) {
    const float3 lo = ((float3)(node->lower[0], node->lower[1], node->lower[2]) - o) * inv_d;
    const float3 hi = ((float3)(node->upper[0], node->upper[1], node->upper[2]) - o) * inv_d;
    const float3 tn = fmin(lo, hi), tf = fmax(lo, hi);
    const float t0 = fmax(fmax(tn.x, tn.y), fmax(tn.z, 0.0f));
    const float t1 = fmin(fmin(tf.x, tf.y), fmin(tf.z, tmax)) * 1.00000024f;  // 2 ulp: no cracks
    return t0 <= t1 ? t0 : PF_INFINITY;
}

float3 pf_safe_inverse(float3 d) {
    const float big = 1e30f;
    return (float3)(d.x != 0.0f ? 1.0f / d.x : copysign(big, d.x),
                    d.y != 0.0f ? 1.0f / d.y : copysign(big, d.y),
                    d.z != 0.0f ? 1.0f / d.z : copysign(big, d.z));
}

// Möller–Trumbore; (u, v) weight vertices 1 and 2, as Embree reports them.
bool pf_intersect_triangle(float3 o, float3 d, float3 p0, float3 p1, float3 p2, float tmax,
                           float* t, float* u, float* v) {
    const float3 e1 = p1 - p0, e2 = p2 - p0;
    const float3 pv = cross(d, e2);
    const float det = dot(e1, pv);
    if (det == 0.0f || !isfinite(det)) return false;
    const float inv_det = 1.0f / det;
    const float3 tv = o - p0;
    const float uu = dot(tv, pv) * inv_det;
    if (uu < 0.0f || uu > 1.0f) return false;
    const float3 qv = cross(tv, e1);
    const float vv = dot(d, qv) * inv_det;
    if (vv < 0.0f || uu + vv > 1.0f) return false;
    const float tt = dot(e2, qv) * inv_det;
    if (!(tt > 0.0f && tt <= tmax)) return false;
    *t = tt;
    *u = uu;
    *v = vv;
    return true;
}

// Defined in shading.cl: whether a material's alpha keeps a candidate hit (glTF MASK / BLEND).
bool pf_alpha_keeps_hit(const PfScene* s, __global const PfMesh* mesh, uint prim, float u, float v,
                        float3 o, float3 d, float t);

// Traverses one instance's mesh BVH with the ray in object space (t stays the world t because
// the direction is transformed, not renormalised). Updates hit; any_hit stops at the first.
bool pf_intersect_mesh(const PfScene* s, uint instance, float3 o, float3 d, float tmax,
                       PfHit* hit, bool any_hit) {
    __global const PfMesh* mesh = &s->meshes[s->instances[instance].mesh];
    if (mesh->node_count == 0) return false;
    __global const PfBvhNode* nodes = s->nodes + mesh->first_node;
    __global const uint* prims = s->prims + mesh->first_prim;
    __global const uint* idx = s->indices + mesh->first_index;
    __global const float* pos = s->positions + 3 * (size_t)mesh->first_vertex;
    const float3 inv_d = pf_safe_inverse(d);
    uint stack[PF_STACK_SIZE];
    int top = 0;
    uint node = 0;
    bool found = false;
    for (;;) {
        __global const PfBvhNode* n = &nodes[node];
        if (pf_box_entry(n, o, inv_d, tmax) != PF_INFINITY) {
            if (n->count == 0) {
                if (top < PF_STACK_SIZE) stack[top++] = n->first;
                node = node + 1;
                continue;
            }
            for (uint k = 0; k < n->count; ++k) {
                const uint tri = prims[n->first + k];
                const float3 p0 = pf_load3(pos + 3 * idx[3 * tri]);
                const float3 p1 = pf_load3(pos + 3 * idx[3 * tri + 1]);
                const float3 p2 = pf_load3(pos + 3 * idx[3 * tri + 2]);
                float t, u, v;
                if (pf_intersect_triangle(o, d, p0, p1, p2, tmax, &t, &u, &v)) {
                    if ((mesh->flags & PF_MESH_ALPHA_TESTED) &&
                        !pf_alpha_keeps_hit(s, mesh, tri, u, v, o, d, t))
                        continue;
                    found = true;
                    if (any_hit) return true;
                    tmax = t;
                    hit->t = t;
                    hit->instance = instance;
                    hit->prim = tri;
                    hit->u = u;
                    hit->v = v;
                }
            }
        }
        if (top == 0) break;
        node = stack[--top];
    }
    return found;
}

// Closest hit (any_hit false) or any hit on (0, ray.tmax].
bool pf_trace(const PfScene* s, PfRay ray, PfHit* hit, bool any_hit) {
    if (s->globals->instance_count == 0) return false;
    const float3 inv_d = pf_safe_inverse(ray.d);
    float tmax = ray.tmax;
    uint stack[PF_STACK_SIZE];
    int top = 0;
    uint node = 0;
    bool found = false;
    for (;;) {
        __global const PfBvhNode* n = &s->top_nodes[node];
        if (pf_box_entry(n, ray.o, inv_d, tmax) != PF_INFINITY) {
            if (n->count == 0) {
                if (top < PF_STACK_SIZE) stack[top++] = n->first;
                node = node + 1;
                continue;
            }
            for (uint k = 0; k < n->count; ++k) {
                const uint inst = s->top_prims[n->first + k];
                __global const float* w2o = s->instances[inst].world_to_object;
                const float3 o = pf_xform_point(w2o, ray.o);
                const float3 d = pf_xform_vector(w2o, ray.d);
                if (pf_intersect_mesh(s, inst, o, d, tmax, hit, any_hit)) {
                    if (any_hit) return true;
                    found = true;
                    tmax = hit->t;
                }
            }
        }
        if (top == 0) break;
        node = stack[--top];
    }
    return found;
}
