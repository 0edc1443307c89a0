// The balancing schemes of Brigade's Table 1 and a cost-predictive one.
#include "coordinator/balance/balancer.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pathfarm::coord {
namespace {

int units_of(const RowRange& r) { return (r.rows() + kRowsPerWorkUnit - 1) / kRowsPerWorkUnit; }

// Speed of a tracer in units per ms; tracers without a measurement get the mean of the others.
std::vector<double> unit_speeds(const BalanceInput& in) {
    std::vector<double> speed(in.last.size(), 0.0);
    double sum = 0.0;
    int known = 0;
    for (std::size_t i = 0; i < in.last.size(); ++i)
        if (!in.last[i].rows.empty() && in.last[i].render_ms > 0.0) {
            speed[i] = units_of(in.last[i].rows) / in.last[i].render_ms;
            sum += speed[i];
            ++known;
        }
    for (double& s : speed)
        if (s <= 0.0) s = known > 0 ? sum / known : 1.0;
    return speed;
}

bool have_last_split(const BalanceInput& in) {
    int covered = 0;
    for (const TracerFrame& t : in.last)
        covered += t.rows.rows();
    return covered == in.height &&
           std::all_of(in.last.begin(), in.last.end(),
                       [](const TracerFrame& t) { return !t.rows.empty() && t.render_ms > 0.0; });
}

class NoBalancing final : public Balancer {
public:
    std::string name() const override { return "none"; }
    std::vector<RowRange> assign(const BalanceInput& in) override {
        return split_rows_equally(in.height, int(in.last.size()));
    }
};

// The last finisher passes one unit to the first finisher (Brigade "Robin Hood").
class RobinHood final : public Balancer {
public:
    std::string name() const override { return "robin-hood"; }
    std::vector<RowRange> assign(const BalanceInput& in) override {
        if (!have_last_split(in)) return split_rows_equally(in.height, int(in.last.size()));
        std::vector<int> units;
        for (const TracerFrame& t : in.last)
            units.push_back(units_of(t.rows));
        const auto by_time = [&](std::size_t a, std::size_t b) {
            return in.last[a].render_ms < in.last[b].render_ms;
        };
        std::vector<std::size_t> order(in.last.size());
        std::iota(order.begin(), order.end(), 0);
        const std::size_t first = *std::min_element(order.begin(), order.end(), by_time);
        const std::size_t last = *std::max_element(order.begin(), order.end(), by_time);
        if (first != last && units[last] > 1) {
            --units[last];
            ++units[first];
        }
        return ranges_from_units(units, in.height);
    }
};

// P_w = (units_w / time_w) / sum(units / time), optionally smoothed S = a P + (1 - a) S.
class Perfect final : public Balancer {
public:
    explicit Perfect(double alpha) : alpha_(alpha) {}
    std::string name() const override { return alpha_ >= 1.0 ? "perfect" : "perfect-smooth"; }
    std::vector<RowRange> assign(const BalanceInput& in) override {
        if (!have_last_split(in)) {
            smoothed_.clear();
            return split_rows_equally(in.height, int(in.last.size()));
        }
        std::vector<double> share = unit_speeds(in);
        const double total = std::accumulate(share.begin(), share.end(), 0.0);
        for (double& s : share)
            s /= total;
        if (smoothed_.size() != share.size()) smoothed_ = share;
        for (std::size_t i = 0; i < share.size(); ++i)
            smoothed_[i] = alpha_ * share[i] + (1.0 - alpha_) * smoothed_[i];
        return ranges_from_units(
            units_from_shares(alpha_ >= 1.0 ? share : smoothed_, work_units(in.height)), in.height);
    }

private:
    double alpha_;
    std::vector<double> smoothed_;
};

// Ours: last frame's cost of every unit predicts this frame's; each tracer's speed is what its
// range cost divided by its time; cut the prefix sum of predicted cost so every tracer's
// predicted finish time (cost / speed) is equal.
class CostPredictive final : public Balancer {
public:
    explicit CostPredictive(double speed_alpha) : alpha_(speed_alpha) {}
    std::string name() const override { return "cost-predictive"; }
    bool steals_mid_frame() const override { return true; }
    std::vector<RowRange> assign(const BalanceInput& in) override {
        const int units = work_units(in.height);
        if (!have_last_split(in) || int(in.unit_cost.size()) != units) {
            smoothed_.clear();
            return Perfect(1.0).assign(in);  // no cost map yet: fall back to speeds
        }
        std::vector<double> prefix(std::size_t(units) + 1, 0.0);
        for (int u = 0; u < units; ++u)
            prefix[std::size_t(u) + 1] =
                prefix[std::size_t(u)] + std::max(in.unit_cost[std::size_t(u)], 1e-9);
        std::vector<double> speed(in.last.size());
        for (std::size_t i = 0; i < in.last.size(); ++i) {
            const int u0 = in.last[i].rows.y0 / kRowsPerWorkUnit,
                      u1 = (in.last[i].rows.y1 + kRowsPerWorkUnit - 1) / kRowsPerWorkUnit;
            speed[i] =
                in.last[i].cost_per_ms > 0.0
                    ? in.last[i].cost_per_ms
                    : (prefix[std::size_t(u1)] - prefix[std::size_t(u0)]) / in.last[i].render_ms;
        }
        smooth(speed);
        return ranges_from_units(cut_prefix(prefix, speed), in.height);
    }

private:
    // Units per tracer, in row order: each tracer's share of the cost still to assign is in
    // proportion to its speed; of the two unit boundaries around that share, the one that ends
    // this tracer and the rest (at their total speed) sooner. The boundary nearest in cost
    // instead gave a slow tracer a unit that cost it twice what it saved the fast one: live,
    // 1.7 % idle against Perfect Smooth's 1.2 % on Sponza (docs/balancing.md).
    static std::vector<int> cut_prefix(const std::vector<double>& prefix,
                                       const std::vector<double>& speed) {
        const int units = int(prefix.size()) - 1;
        double rest_speed = std::accumulate(speed.begin(), speed.end(), 0.0);
        std::vector<int> counts;
        int begin = 0;
        for (std::size_t i = 0; i + 1 < speed.size(); ++i) {
            const double remaining = prefix.back() - prefix[std::size_t(begin)];
            const double target = prefix[std::size_t(begin)] + remaining * speed[i] / rest_speed;
            rest_speed -= speed[i];
            const auto finish = [&](int c) {
                return std::max((prefix[std::size_t(c)] - prefix[std::size_t(begin)]) / speed[i],
                                (prefix.back() - prefix[std::size_t(c)]) / rest_speed);
            };
            int cut = int(std::lower_bound(prefix.begin() + begin, prefix.end(), target) -
                          prefix.begin());
            if (cut > begin && finish(cut - 1) <= finish(cut)) --cut;
            cut = std::clamp(cut, begin, std::max(begin, units - int(speed.size() - 1 - i)));
            counts.push_back(cut - begin);
            begin = cut;
        }
        counts.push_back(units - begin);
        return counts;
    }

    // One frame's speed measurement is noisy (the split is cut on it); the tracers' speeds change
    // slowly, and a sudden change within a frame is the steal's to absorb.
    void smooth(std::vector<double>& speed) {
        if (smoothed_.size() != speed.size()) smoothed_ = speed;
        for (std::size_t i = 0; i < speed.size(); ++i)
            speed[i] = smoothed_[i] = alpha_ * speed[i] + (1.0 - alpha_) * smoothed_[i];
    }

    double alpha_;
    std::vector<double> smoothed_;
};

}  // namespace

int work_units(int height) { return (height + kRowsPerWorkUnit - 1) / kRowsPerWorkUnit; }

std::vector<RowRange> ranges_from_units(const std::vector<int>& units, int height) {
    std::vector<RowRange> out;
    int y = 0;
    for (int u : units) {
        const int y1 = std::min(height, y + u * kRowsPerWorkUnit);
        out.push_back({y, y1});
        y = y1;
    }
    if (!out.empty()) out.back().y1 = height;
    return out;
}

std::vector<int> units_from_shares(const std::vector<double>& shares, int total) {
    std::vector<int> units(shares.size());
    std::vector<std::pair<double, std::size_t>> remainders;
    int assigned = 0;
    for (std::size_t i = 0; i < shares.size(); ++i) {
        const double exact = shares[i] * total;
        units[i] = int(std::floor(exact));
        assigned += units[i];
        remainders.emplace_back(exact - units[i], i);
    }
    std::sort(remainders.begin(), remainders.end(), std::greater<>());
    for (int k = 0; assigned < total; ++k, ++assigned)
        ++units[remainders[std::size_t(k) % remainders.size()].second];
    return units;
}

std::unique_ptr<Balancer> make_balancer(const std::string& name, double smooth_alpha,
                                        double speed_smoothing) {
    if (name == "none") return std::make_unique<NoBalancing>();
    if (name == "robin-hood") return std::make_unique<RobinHood>();
    if (name == "perfect") return std::make_unique<Perfect>(1.0);
    if (name == "perfect-smooth") return std::make_unique<Perfect>(smooth_alpha);
    if (name == "cost-predictive" || name == "ours")
        return std::make_unique<CostPredictive>(speed_smoothing);
    return nullptr;
}

std::vector<std::string> balancer_names() {
    return {"none", "robin-hood", "perfect", "perfect-smooth", "cost-predictive"};
}

}  // namespace pathfarm::coord
