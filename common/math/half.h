// Float to IEEE half bits exactly as glm::packHalf1x16 rounds (half way rounds away from zero,
// not to even; overflow gives infinity; NaN stays NaN), without its branches: the rounding
// branch is a coin toss wherever values vary, and first-hit planes convert eight values a pixel
// (first_hits.cpp). 320x180 x 8 values: glm 2.8 ms where every value differs (textures, curved
// surfaces), 1.3 ms where a quarter do, 0.77 ms in flat runs of 50; this 0.69 ms in all three.
// Checked against glm for every one of the 2^32 floats once (2026-12-07: no difference), and on
// every exponent and rounding pattern by HalfBits.* each run.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace pathfarm {

inline uint16_t half_bits(float f) {
    uint32_t i;
    std::memcpy(&i, &f, sizeof i);
    const uint32_t sign = (i >> 16) & 0x8000u;
    const int32_t e = int32_t((i >> 23) & 0xffu) - (127 - 15);  // the half's biased exponent
    const uint32_t m = i & 0x7fffffu;
    // A normal half: the rounding carry may ripple into the exponent, which the addition keeps;
    // past the largest exponent it is infinity.
    const uint32_t rounded = m + ((m & 0x1000u) << 1);
    const uint32_t normal = std::min((uint32_t(e) << 10) + (rounded >> 13), 0x7c00u);
    // Below the normal range: the significand with its hidden bit, shifted down (zero far below;
    // the shift is computed for every value and clamped so that none is undefined).
    const uint32_t d = (m | 0x800000u) >> uint32_t(std::clamp(1 - e, 0, 31));
    const uint32_t denormal = (d + ((d & 0x1000u) << 1)) >> 13;
    // Infinity and NaN (a NaN whose kept bits are all zero keeps one, or it would be infinity).
    const uint32_t kept = m >> 13;
    const uint32_t special = 0x7c00u | kept | uint32_t(m != 0 && kept == 0);
    return uint16_t(sign | (e <= 0 ? denormal : e == 255 - (127 - 15) ? special : normal));
}

// IEEE half bits to the float glm::unpackHalf1x16 gives, without its branches and loop (the
// coordinator unpacks eight a pixel of every tile's first hits). The half's exponent and
// significand shifted into a float's place and rebiased; infinity and NaN rebiased once more to
// the float's top exponent; a denormal half made a normal float by adding the hidden bit and
// subtracting it again as 2^-14 (exact). Checked against glm for all 65536 halves (HalfFloat.*).
inline float half_to_float(uint16_t h) {
    const uint32_t shifted = uint32_t(h & 0x7fffu) << 13;
    const uint32_t exponent = shifted & (0x7c00u << 13);
    const uint32_t normal = shifted + ((127u - 15u) << 23);
    const uint32_t special = normal + ((128u - 16u) << 23);
    float denormal, two_to_minus_14;
    const uint32_t denormal_bits = normal + (1u << 23), minus_14 = 113u << 23;
    std::memcpy(&denormal, &denormal_bits, sizeof denormal);
    std::memcpy(&two_to_minus_14, &minus_14, sizeof two_to_minus_14);
    denormal -= two_to_minus_14;
    uint32_t denormal_out;
    std::memcpy(&denormal_out, &denormal, sizeof denormal_out);
    const uint32_t bits = (exponent == (0x7c00u << 13) ? special
                           : exponent == 0             ? denormal_out
                                                       : normal) |
                          (uint32_t(h & 0x8000u) << 16);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

}  // namespace pathfarm
