// The extra-sample plan: young pixels first, round by round, never over the budget, the rest
// dithered evenly, every pixel in turn.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "coordinator/pacing/extra_samples.h"

namespace pathfarm::coord::extra_samples_test {
namespace {

constexpr int kW = 64, kH = 48;
constexpr std::size_t kPixels = std::size_t(kW) * kH;

std::size_t total(const std::vector<uint8_t>& map) {
    std::size_t n = 0;
    for (const uint8_t e : map)
        n += e;
    return n;
}

// Long history everywhere but a disk of pixels seen for the first time (a disocclusion).
std::vector<float> history_with_hole(float cx, float cy, float radius) {
    std::vector<float> h(kPixels, 40.0f);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (std::hypot(x - cx, y - cy) <= radius) h[std::size_t(y) * kW + x] = 1.0f;
    return h;
}

// Whether pixel (x, y) is within kReach of a pixel of the hole.
bool near_hole(const std::vector<float>& h, int x, int y) {
    const int r = ExtraSamplePlan::kReach;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const int px = x + dx, py = y + dy;
            if (px >= 0 && py >= 0 && px < kW && py < kH && h[std::size_t(py) * kW + px] < 2.0f)
                return true;
        }
    return false;
}

TEST(ExtraSamplePlan, YoungPixelsTakeTheBudgetRoundByRoundBeforeTheDither) {
    const std::vector<float> h = history_with_hole(20.0f, 30.0f, 5.0f);
    std::size_t young = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            young += near_hole(h, x, y);
    ASSERT_GT(young, 100u);
    // Less than one round: every extra sample on a young pixel, none with two.
    const double one_round = 0.5 * double(young) / double(kPixels);
    std::vector<uint8_t> map = plan_extra_samples(h, kW, kH, one_round, 3);
    EXPECT_EQ(total(map), std::size_t(std::llround(one_round * kPixels)));
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const uint8_t e = map[std::size_t(y) * kW + x];
            EXPECT_LE(e, near_hole(h, x, y) ? 1 : 0) << x << "," << y;
        }
    // Room for every round and more: each young pixel takes three (its history of one frame
    // plus three makes four), the rest is dithered over the frame, one more at most anywhere.
    const double plenty = (3.0 * double(young) + 0.25 * double(kPixels)) / double(kPixels);
    map = plan_extra_samples(h, kW, kH, plenty, 3);
    EXPECT_LE(total(map), std::size_t(std::llround(plenty * kPixels)));
    EXPECT_GE(total(map), std::size_t(std::llround(plenty * kPixels)) - kPixels / 64);
    std::size_t dithered_mature = 0, mature = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const uint8_t e = map[std::size_t(y) * kW + x];
            if (near_hole(h, x, y)) {
                EXPECT_GE(e, 3) << x << "," << y;
                EXPECT_LE(e, 4) << x << "," << y;
            } else {
                EXPECT_LE(e, 1);
                dithered_mature += e;
                ++mature;
            }
        }
    EXPECT_NEAR(double(dithered_mature) / double(mature), 0.25, 0.03);
}

// Random histories and budgets: never more than the budget, and the whole budget but for the
// dither's last step (1/64 of the pixels).
TEST(ExtraSamplePlan, SpendsTheBudgetAndNoMore) {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 40; ++trial) {
        std::vector<float> h(kPixels);
        const float young_share = std::uniform_real_distribution<float>(0.0f, 0.3f)(rng);
        for (float& f : h)
            f = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng) < young_share
                    ? float(1 + rng() % 4)
                    : 30.0f;
        const double budget = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
        const std::vector<uint8_t> map = plan_extra_samples(h, kW, kH, budget, uint64_t(trial));
        const auto allowed = std::size_t(std::llround(budget * kPixels));
        EXPECT_LE(total(map), allowed) << "trial " << trial;
        EXPECT_GE(total(map) + kPixels / 64, allowed) << "trial " << trial;
    }
}

// Without history (or with another size's) the dither alone: every 8x8 block the same count,
// and over 64 frames every pixel takes exactly its share.
TEST(ExtraSamplePlan, TheDitherIsEvenAndVisitsEveryPixelInTurn) {
    const std::vector<float> other_size(100, 1.0f);
    std::vector<int> visits(kPixels, 0);
    for (uint64_t frame = 0; frame < 64; ++frame) {
        const std::vector<uint8_t> map =
            plan_extra_samples(frame % 2 ? other_size : std::vector<float>{}, kW, kH, 0.125, frame);
        for (int by = 0; by < kH; by += 8)
            for (int bx = 0; bx < kW; bx += 8) {
                int n = 0;
                for (int y = by; y < by + 8; ++y)
                    for (int x = bx; x < bx + 8; ++x)
                        n += map[std::size_t(y) * kW + x];
                EXPECT_EQ(n, 8) << "block " << bx << "," << by << " frame " << frame;
            }
        for (std::size_t p = 0; p < kPixels; ++p)
            visits[p] += map[p];
    }
    for (std::size_t p = 0; p < kPixels; ++p)
        EXPECT_EQ(visits[p], 8) << "pixel " << p;
}

TEST(ExtraSamplePlan, NoBudgetNoSamples) {
    EXPECT_EQ(total(plan_extra_samples(history_with_hole(5, 5, 3), kW, kH, 0.0, 1)), 0u);
    EXPECT_TRUE(plan_extra_samples({}, 0, 0, 0.5, 1).empty());
}

}  // namespace
}  // namespace pathfarm::coord::extra_samples_test
