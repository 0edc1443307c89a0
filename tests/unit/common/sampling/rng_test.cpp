// PixelSampler: determinism, range, and the stratification Owen-scrambled Sobol promises.
#include "common/sampling/rng.h"

#include <set>

#include <gtest/gtest.h>

namespace pathfarm {
namespace {

TEST(PixelSampler, SameInputsGiveSameNumbers) {
    PixelSampler a(3, 7, 2, 5, 42), b(3, 7, 2, 5, 42);
    for (int i = 0; i < 20; ++i) {
        const Vec2 x = a.next_2d(), y = b.next_2d();
        EXPECT_EQ(x.x, y.x);
        EXPECT_EQ(x.y, y.y);
    }
}

TEST(PixelSampler, EveryInputChangesTheNumbers) {
    const Vec2 base = PixelSampler(3, 7, 2, 5, 42).next_2d();
    for (const Vec2 other :
         {PixelSampler(4, 7, 2, 5, 42).next_2d(), PixelSampler(3, 8, 2, 5, 42).next_2d(),
          PixelSampler(3, 7, 3, 5, 42).next_2d(), PixelSampler(3, 7, 2, 6, 42).next_2d(),
          PixelSampler(3, 7, 2, 5, 43).next_2d()})
        EXPECT_NE(base, other);
}

TEST(PixelSampler, ValuesLieInUnitSquare) {
    for (uint32_t s = 0; s < 1000; ++s) {
        PixelSampler p(s % 17, s % 5, 1, s, 9);
        for (int d = 0; d < 8; ++d) {
            const Vec2 u = p.next_2d();
            EXPECT_GE(u.x, 0.0f);
            EXPECT_LT(u.x, 1.0f);
            EXPECT_GE(u.y, 0.0f);
            EXPECT_LT(u.y, 1.0f);
        }
    }
}

// The first 2^m samples of every dimension pair form a (0, m, 2)-net: each elementary
// interval of area 2^-m holds exactly one point.
TEST(PixelSampler, FirstPowerOfTwoSamplesAreStratified) {
    constexpr int kLog2 = 6, kCount = 1 << kLog2;
    for (int pair = 0; pair < 5; ++pair) {
        std::vector<Vec2> pts;
        for (int s = 0; s < kCount; ++s) {
            PixelSampler p(11, 13, 0, uint32_t(s), 7);
            Vec2 u;
            for (int d = 0; d <= pair; ++d)
                u = p.next_2d();
            pts.push_back(u);
        }
        for (int a = 0; a <= kLog2; ++a) {
            const int nx = 1 << a, ny = 1 << (kLog2 - a);
            std::set<int> cells;
            for (const Vec2& u : pts)
                cells.insert(int(u.x * nx) * ny + int(u.y * ny));
            EXPECT_EQ(int(cells.size()), kCount) << "pair " << pair << " grid " << nx << "x" << ny;
        }
    }
}

TEST(PixelSampler, TableFormulationEqualsTheDefinition) {
    Pcg32 rng(77);
    for (int i = 0; i < 10000; ++i) {
        const uint32_t w = rng.next_u32();
        EXPECT_EQ(detail::reversed_sobol_dim1_of_reversed(w),
                  reverse_bits(sobol_dim1(reverse_bits(w))));
    }
}

TEST(Pcg32, KnownFirstValuesAreStable) {
    Pcg32 a(1), b(1), c(2);
    EXPECT_EQ(a.next_u32(), b.next_u32());
    EXPECT_NE(Pcg32(1).next_u32(), c.next_u32());
}

}  // namespace
}  // namespace pathfarm
