// A cumulative distribution searched through a guide table (Chen and Asau 1974; Devroye,
// "Non-Uniform Random Variate Generation", III.2.4): bucket j of M holds the first entry above
// j / M, so a number in [j / M, (j + 1) / M) is searched for only between its bucket's entry and
// the next bucket's, a step or two instead of a binary search over every entry (13 unpredictable
// branches for 5 000 emitters). The answer is std::upper_bound's to the bit: where rounding puts
// a number in a bucket that does not hold its answer, a check finds it and the whole range is
// searched instead.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace pathfarm {

class GuidedCdf {
public:
    GuidedCdf() = default;
    // `cdf` must not decrease; one bucket per entry.
    explicit GuidedCdf(std::vector<float> cdf) : cdf_(std::move(cdf)) {
        const std::size_t m = cdf_.size();
        if (m == 0) return;  // upper_bound() answers 0 without a guide
        guide_.resize(m + 1);
        std::size_t i = 0;
        for (std::size_t j = 0; j <= m; ++j) {
            const float threshold = float(j) / float(m);
            while (i < m && !(cdf_[i] > threshold))
                ++i;
            guide_[j] = uint32_t(i);
        }
    }

    // The normalised cumulative sum of non-negative weights (uniform when they sum to zero),
    // its last entry exactly 1.
    static GuidedCdf from_weights(const std::vector<double>& weights) {
        double total = 0.0;
        for (double w : weights)
            total += w;
        std::vector<float> cdf(weights.size());
        double acc = 0.0;
        for (std::size_t k = 0; k < weights.size(); ++k) {
            acc += weights[k];
            cdf[k] = total > 0.0 ? float(acc / total) : float(k + 1) / float(weights.size());
        }
        if (!cdf.empty()) cdf.back() = 1.0f;
        return GuidedCdf(std::move(cdf));
    }

    const std::vector<float>& values() const { return cdf_; }
    // guide()[j]: the first entry above j / size(), for j in [0, size()] (empty if size() is 0).
    const std::vector<uint32_t>& guide() const { return guide_; }
    std::size_t size() const { return cdf_.size(); }
    bool empty() const { return cdf_.empty(); }
    // The probability of entry k (its step in the CDF).
    float pmf(std::size_t k) const { return cdf_[k] - (k > 0 ? cdf_[k - 1] : 0.0f); }

    // The index of the first entry greater than u (size() if none), as std::upper_bound.
    std::size_t upper_bound(float u) const {
        const std::size_t m = cdf_.size();
        const float scaled = u * float(m);
        if (scaled >= 0.0f && scaled < float(m)) {
            const auto j = std::size_t(scaled);
            const std::size_t lo = guide_[j], hi = guide_[j + 1];
            const std::size_t k = std::size_t(
                std::upper_bound(cdf_.begin() + lo, cdf_.begin() + hi, u) - cdf_.begin());
            // (An empty distribution never gets here: it goes to the whole search, answering 0.)
            // upper_bound's answer is k exactly when everything before k is at most u and the
            // entry at k (if any) is above it.
            if ((k == 0 || !(cdf_[k - 1] > u)) && (k == m || cdf_[k] > u)) return k;
        }
        return std::size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
    }

private:
    std::vector<float> cdf_;
    std::vector<uint32_t> guide_;  // guide_[j]: the first entry above j / size()
};

}  // namespace pathfarm
