// half_bits (common/math/half.h) gives glm::packHalf1x16's bits: the first hits' planes change
// converter, not content.
#include "common/math/half.h"

#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <glm/gtc/packing.hpp>

namespace pathfarm::half_test {
namespace {

float from_bits(uint32_t bits) {
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

// Every sign and exponent, with every pattern of the 13 mantissa bits the rounding looks at and
// carries through, under several patterns of the 10 bits kept; then random floats.
TEST(HalfBits, AgreeWithGlmOnEveryExponentAndRoundingPattern) {
    const uint32_t kept[] = {0x000, 0x001, 0x155, 0x2aa, 0x3fe, 0x3ff};
    int64_t checked = 0, mismatches = 0;
    auto check = [&](uint32_t bits) {
        const float f = from_bits(bits);
        const uint16_t ours = half_bits(f), glms = glm::packHalf1x16(f);
        if (ours != glms && ++mismatches <= 5)
            ADD_FAILURE() << std::hex << "float bits 0x" << bits << ": 0x" << ours << ", glm 0x"
                          << glms;
        ++checked;
    };
    for (uint32_t se = 0; se < 512; ++se)
        for (uint32_t hi : kept)
            for (uint32_t lo = 0; lo < 0x2000; ++lo)
                check((se << 23) | (hi << 13) | lo);
    std::mt19937 rng(7);
    for (int k = 0; k < 1'000'000; ++k)
        check(uint32_t(rng()));
    EXPECT_EQ(mismatches, 0) << "of " << checked;
}

// Every half (zeros, denormals, normals, infinities, NaNs, both signs) unpacks to glm's
// float, bit for bit.
TEST(HalfFloat, AgreesWithGlmOnEveryHalf) {
    int wrong = 0;
    for (uint32_t h = 0; h <= 0xffffu; ++h) {
        const float ours = half_to_float(uint16_t(h)), glms = glm::unpackHalf1x16(uint16_t(h));
        uint32_t a, b;
        std::memcpy(&a, &ours, sizeof a);
        std::memcpy(&b, &glms, sizeof b);
        wrong += a != b;
    }
    EXPECT_EQ(wrong, 0);
}

}  // namespace
}  // namespace pathfarm::half_test
