// The guide table must answer exactly as std::upper_bound over the whole distribution, for any
// distribution the light sampler can build and any number: random distributions (zero-power
// runs, equal entries, powers spanning 12 orders of magnitude, sizes 1 to 5 000), searched at
// random numbers and at the numbers where rounding decides (every entry and its neighbours,
// every bucket's edge and its neighbours, 0, 1 and just below 1).
#include "common/sampling/guided_cdf.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/sampling/rng.h"

namespace pathfarm {
namespace {

// A normalised cumulative distribution of random powers, as LightSampler builds its own.
std::vector<float> random_cdf(Pcg32& rng, std::size_t n) {
    std::vector<double> power(n);
    for (double& p : power) {
        const float kind = rng.next_float();
        if (kind < 0.2f) {
            p = 0.0;  // emitters of no power: runs of equal entries
        } else if (kind < 0.4f) {
            p = 1.0;  // equal powers
        } else {
            p = std::pow(10.0, 12.0 * double(rng.next_float()) - 6.0);
        }
    }
    return GuidedCdf::from_weights(power).values();
}

std::size_t full_search(const std::vector<float>& cdf, float u) {
    return std::size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
}

TEST(GuidedCdf, AnswersAsTheWholeBinarySearchForRandomDistributionsAndEdges) {
    Pcg32 rng(20261207);
    std::size_t checked = 0, mismatches = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const auto n = std::size_t(1 + (trial < 30 ? trial : rng.next_u32() % 5000));
        const std::vector<float> cdf = random_cdf(rng, n);
        const GuidedCdf guided(cdf);
        ASSERT_EQ(guided.values(), cdf);
        std::vector<float> probes = {0.0f, 1.0f, std::nextafter(1.0f, 0.0f), -0.0f};
        for (int k = 0; k < 200; ++k)
            probes.push_back(rng.next_float());
        for (float c : cdf) {
            probes.push_back(c);
            probes.push_back(std::nextafter(c, 0.0f));
            probes.push_back(std::nextafter(c, 2.0f));
        }
        for (std::size_t j = 0; j <= n; ++j) {
            const float edge = float(j) / float(n);
            probes.push_back(edge);
            probes.push_back(std::nextafter(edge, 0.0f));
            probes.push_back(std::nextafter(edge, 2.0f));
        }
        for (float u : probes) {
            ++checked;
            if (guided.upper_bound(u) != full_search(cdf, u)) {
                if (++mismatches <= 5)
                    ADD_FAILURE() << "n=" << n << " u=" << u << ": " << guided.upper_bound(u)
                                  << " against " << full_search(cdf, u);
            }
        }
    }
    EXPECT_EQ(mismatches, 0u) << "of " << checked;
    EXPECT_GT(checked, 1000000u);
}

TEST(GuidedCdf, AnEmptyDistributionHasNothingToFind) {
    for (const GuidedCdf& none : {GuidedCdf(), GuidedCdf(std::vector<float>{})}) {
        EXPECT_TRUE(none.empty());
        EXPECT_EQ(none.upper_bound(0.5f), 0u);
    }
}

}  // namespace
}  // namespace pathfarm
