// Random numbers. PixelSampler draws the dimensions of one path sample from a hash of
// (x, y, frame, sample, seed) as DESIGN.md's determinism contract requires: no thread or tracer
// state enters. Pcg32 is an independent stream for tests and offline tools.
#pragma once

#include <cstdint>

#include "common/base/hash.h"
#include "common/math/types.h"
#include "common/sampling/sampler_shared.h"

namespace pathfarm {

// The scrambling primitives live in sampler_shared.h, which the OpenCL kernels read too.
inline uint32_t reverse_bits(uint32_t x) { return pf_reverse_bits(x); }
// Maps 32 random bits to [0, 1) with 24 bits of precision (never returns 1).
inline float bits_to_unit_float(uint32_t bits) { return pf_bits_to_unit_float(bits); }
inline uint32_t laine_karras(uint32_t x, uint32_t seed) { return pf_laine_karras(x, seed); }

// Owen scrambling in base 2: bit j flips depending on the seed and on the bits above j.
inline uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
    return reverse_bits(laine_karras(reverse_bits(x), seed));
}

// First two Sobol dimensions (van der Corput, and the x+1 polynomial), 32-bit fixed point.
inline uint32_t sobol_dim0(uint32_t i) { return reverse_bits(i); }
inline uint32_t sobol_dim1(uint32_t i) {
    uint32_t r = 0;
    for (uint32_t v = 1U << 31; i != 0; i >>= 1, v ^= v >> 1)
        if (i & 1U) r ^= v;
    return r;
}

namespace detail {

// reverse_bits(sobol_dim1(reverse_bits(w))) as four byte tables: XOR of the bit-reversed
// direction numbers selected by w's bits.
struct SobolDim1Tables {
    uint32_t table[4][256];
    constexpr SobolDim1Tables() : table{} {
        uint32_t dir[32] = {};
        uint32_t v = 1U << 31;
        for (int k = 0; k < 32; ++k, v ^= v >> 1) {
            uint32_t r = 0;  // reverse_bits(v), spelled out to stay constexpr
            for (int b = 0; b < 32; ++b)
                if (v & (1U << b)) r |= 1U << (31 - b);
            dir[k] = r;
        }
        for (int byte = 0; byte < 4; ++byte)
            for (int value = 0; value < 256; ++value) {
                uint32_t x = 0;
                for (int m = 0; m < 8; ++m)
                    if (value & (1 << m)) x ^= dir[31 - (8 * byte + m)];
                table[byte][value] = x;
            }
    }
};
inline constexpr SobolDim1Tables kSobolDim1{};

inline uint32_t reversed_sobol_dim1_of_reversed(uint32_t w) {
    return kSobolDim1.table[0][w & 0xffU] ^ kSobolDim1.table[1][(w >> 8) & 0xffU] ^
           kSobolDim1.table[2][(w >> 16) & 0xffU] ^ kSobolDim1.table[3][w >> 24];
}

}  // namespace detail

// Samples of pixel (x, y) in a frame: each pair of dimensions is a 2D Owen-scrambled Sobol
// sequence whose sample index is shuffled per pair ("padding"), decorrelated per pixel and
// dimension pair by hashing. Any prefix of 2^k samples of a pair is a stratified (0,k,2)-net.
//
// In formulas (R = reverse_bits, LK = laine_karras, S = nested_uniform_scramble = R∘LK∘R):
//   index = S(sample, k0);  x = S(sobol_dim0(index), k1);  y = S(sobol_dim1(index), k2).
// Since sobol_dim0 = R, this is x = R(LK(R(w), k1)) and y = R(LK(T(w), k2)) with
// w = LK(R(sample), k0) and T the table above: 3 bit reversals per pair instead of 7.
class PixelSampler {
public:
    PixelSampler(uint32_t x, uint32_t y, uint32_t frame, uint32_t sample, uint32_t seed)
        : PixelSampler(pixel_hash(x, y, frame, seed), sample) {}
    // The same sampler from its pixel's hash, which every sample of the pixel shares.
    PixelSampler(uint32_t pixel_hash, uint32_t sample)
        : pixel_hash_(pixel_hash), reversed_sample_(reverse_bits(sample)) {}
    PixelSampler() : PixelSampler(0u, 0u) {}  // for arrays whose entries are assigned
    static uint32_t pixel_hash(uint32_t x, uint32_t y, uint32_t frame, uint32_t seed) {
        return pf_hash_words4(x, y, frame, seed);
    }

    Vec2 next_2d() {
        const uint32_t pair_seed = pf_pair_seed(pixel_hash_, dimension_pair_++);
        const uint32_t w = laine_karras(reversed_sample_, pair_seed);
        const uint32_t a =
            reverse_bits(laine_karras(reverse_bits(w), pf_x_scramble_seed(pair_seed)));
        const uint32_t b = reverse_bits(laine_karras(detail::reversed_sobol_dim1_of_reversed(w),
                                                     pf_y_scramble_seed(pair_seed)));
        return {bits_to_unit_float(a), bits_to_unit_float(b)};
    }
    float next_1d() { return next_2d().x; }

private:
    uint32_t pixel_hash_;
    uint32_t reversed_sample_;
    uint32_t dimension_pair_ = 0;
};

// PCG32 (O'Neill): small, fast and statistically sound independent random numbers.
class Pcg32 {
public:
    explicit Pcg32(uint64_t seed, uint64_t stream = 1) : inc_((stream << 1U) | 1U) {
        next_u32();
        state_ += seed;
        next_u32();
    }
    uint32_t next_u32() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        const auto xorshifted = static_cast<uint32_t>(((old >> 18U) ^ old) >> 27U);
        const auto rot = static_cast<uint32_t>(old >> 59U);
        return (xorshifted >> rot) | (xorshifted << ((32U - rot) & 31U));
    }
    float next_float() { return bits_to_unit_float(next_u32()); }
    Vec2 next_2d() { return {next_float(), next_float()}; }

private:
    uint64_t state_ = 0;
    uint64_t inc_;
};

}  // namespace pathfarm
