// Per-sample random numbers, bit for bit those of common/sampling/rng.h (PixelSampler): the
// hashing and scrambling are common/base/hash_shared.h and common/sampling/sampler_shared.h,
// pasted ahead of this file, so the OpenCL backend draws the numbers the Embree backend draws
// for every sample. (device_types.h precedes them.)

// reverse_bits(sobol_dim1(reverse_bits(w))) from the host's byte tables (XOR of the bit-reversed
// direction numbers that w's bits select).
uint pf_reversed_sobol_dim1_of_reversed(__global const uint* table, uint w) {
    return table[w & 0xffU] ^ table[256 + ((w >> 8) & 0xffU)] ^ table[512 + ((w >> 16) & 0xffU)] ^
           table[768 + (w >> 24)];
}

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
    const uint pair_seed = pf_pair_seed(s->pixel_hash, s->dimension_pair++);
    const uint w = pf_laine_karras(s->reversed_sample, pair_seed);
    const uint a =
        pf_reverse_bits(pf_laine_karras(pf_reverse_bits(w), pf_x_scramble_seed(pair_seed)));
    const uint b = pf_reverse_bits(pf_laine_karras(
        pf_reversed_sobol_dim1_of_reversed(s->sobol_dim1, w), pf_y_scramble_seed(pair_seed)));
    return (float2)(pf_bits_to_unit_float(a), pf_bits_to_unit_float(b));
}
