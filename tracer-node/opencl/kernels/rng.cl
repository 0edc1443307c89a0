// Per-sample random numbers, bit for bit those of common/sampling/rng.h (PixelSampler): the
// same hash of (x, y, frame, seed), the same Owen-scrambled Sobol pairs, so the OpenCL backend
// draws the numbers the Embree backend draws for every sample. (device_types.h precedes this.)

uint pf_hash_u32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

// hash_words({a, b, c, d})
uint pf_hash_words4(uint a, uint b, uint c, uint d) {
    uint h = 0x9e3779b9U;
    h = pf_hash_u32(h ^ pf_hash_u32(a + 0x632be5abU));
    h = pf_hash_u32(h ^ pf_hash_u32(b + 0x632be5abU));
    h = pf_hash_u32(h ^ pf_hash_u32(c + 0x632be5abU));
    h = pf_hash_u32(h ^ pf_hash_u32(d + 0x632be5abU));
    return h;
}

uint pf_reverse_bits(uint x) {
    x = ((x & 0x55555555U) << 1) | ((x >> 1) & 0x55555555U);
    x = ((x & 0x33333333U) << 2) | ((x >> 2) & 0x33333333U);
    x = ((x & 0x0f0f0f0fU) << 4) | ((x >> 4) & 0x0f0f0f0fU);
    x = ((x & 0x00ff00ffU) << 8) | ((x >> 8) & 0x00ff00ffU);
    return (x << 16) | (x >> 16);
}

uint pf_laine_karras(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cU;
    x ^= x * 0xb82f1e52U;
    x ^= x * 0xc7afe638U;
    x ^= x * 0x8d22f6e6U;
    return x;
}

// reverse_bits(sobol_dim1(reverse_bits(w))) from the host's byte tables (XOR of the bit-reversed
// direction numbers that w's bits select).
uint pf_reversed_sobol_dim1_of_reversed(__global const uint* table, uint w) {
    return table[w & 0xffU] ^ table[256 + ((w >> 8) & 0xffU)] ^ table[512 + ((w >> 16) & 0xffU)] ^
           table[768 + (w >> 24)];
}

float pf_bits_to_unit_float(uint bits) { return (float)(bits >> 8) * 5.9604644775390625e-8f; }

typedef struct {
    uint pixel_hash;
    uint reversed_sample;
    uint dimension_pair;
    __global const uint* sobol_dim1;  // PfSceneGlobals::sobol_dim1
} PfSampler;

PfSampler pf_make_sampler(uint x, uint y, uint frame, uint sample, uint seed,
                          __global const uint* sobol_dim1) {
    PfSampler s;
    s.sobol_dim1 = sobol_dim1;
    s.pixel_hash = pf_hash_words4(x, y, frame, seed);
    s.reversed_sample = pf_reverse_bits(sample);
    s.dimension_pair = 0;
    return s;
}

float2 pf_next_2d(PfSampler* s) {
    const uint pair_seed = pf_hash_u32(s->pixel_hash ^ (s->dimension_pair++ * 0x9e3779b9U));
    const uint w = pf_laine_karras(s->reversed_sample, pair_seed);
    const uint a = pf_reverse_bits(
        pf_laine_karras(pf_reverse_bits(w), pf_hash_u32(pair_seed ^ 0x68bc21ebU)));
    const uint b = pf_reverse_bits(pf_laine_karras(pf_reversed_sobol_dim1_of_reversed(s->sobol_dim1, w),
                                                   pf_hash_u32(pair_seed ^ 0x02e5be93U)));
    return (float2)(pf_bits_to_unit_float(a), pf_bits_to_unit_float(b));
}
