// Random numbers. PixelSampler draws the dimensions of one path sample from a hash of
// (x, y, frame, sample, seed) as DESIGN.md's determinism contract requires: no thread or tracer
// state enters. Pcg32 is an independent stream for tests and offline tools.
#pragma once

#include <cstdint>

#include "common/base/hash.h"
#include "common/math/types.h"

namespace pathfarm {

inline uint32_t reverse_bits(uint32_t x) {
    x = ((x & 0x55555555U) << 1) | ((x >> 1) & 0x55555555U);
    x = ((x & 0x33333333U) << 2) | ((x >> 2) & 0x33333333U);
    x = ((x & 0x0f0f0f0fU) << 4) | ((x >> 4) & 0x0f0f0f0fU);
    x = ((x & 0x00ff00ffU) << 8) | ((x >> 8) & 0x00ff00ffU);
    return (x << 16) | (x >> 16);
}

// Maps 32 random bits to [0, 1) with 24 bits of precision (never returns 1).
inline float bits_to_unit_float(uint32_t bits) { return float(bits >> 8) * 0x1p-24f; }

// Owen scrambling in base 2 via a hash (Burley 2020, "Practical Hash-based Owen Scrambling"):
// bit j of the result flips depending only on the seed and on the bits above j.
inline uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
    x = reverse_bits(x);
    x += seed;
    x ^= x * 0x6c50b47cU;
    x ^= x * 0xb82f1e52U;
    x ^= x * 0xc7afe638U;
    x ^= x * 0x8d22f6e6U;
    return reverse_bits(x);
}

// First two Sobol dimensions (van der Corput, and the x+1 polynomial), 32-bit fixed point.
inline uint32_t sobol_dim0(uint32_t i) { return reverse_bits(i); }
inline uint32_t sobol_dim1(uint32_t i) {
    uint32_t r = 0;
    for (uint32_t v = 1U << 31; i != 0; i >>= 1, v ^= v >> 1)
        if (i & 1U) r ^= v;
    return r;
}

// Samples of pixel (x, y) in a frame: each pair of dimensions is a 2D Owen-scrambled Sobol
// sequence whose sample index is shuffled per pair ("padding"), decorrelated per pixel and
// dimension pair by hashing. Any prefix of 2^k samples of a pair is a stratified (0,k,2)-net.
class PixelSampler {
public:
    PixelSampler(uint32_t x, uint32_t y, uint32_t frame, uint32_t sample, uint32_t seed)
        : pixel_hash_(hash_words({x, y, frame, seed})), sample_(sample) {}

    Vec2 next_2d() {
        const uint32_t pair_seed = hash_words({pixel_hash_, dimension_pair_++});
        const uint32_t index = nested_uniform_scramble(sample_, hash_u32(pair_seed ^ 0xa511e9b3U));
        const uint32_t a = nested_uniform_scramble(sobol_dim0(index), hash_u32(pair_seed + 1U));
        const uint32_t b = nested_uniform_scramble(sobol_dim1(index), hash_u32(pair_seed + 2U));
        return {bits_to_unit_float(a), bits_to_unit_float(b)};
    }
    float next_1d() { return next_2d().x; }

private:
    uint32_t pixel_hash_;
    uint32_t sample_;
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
