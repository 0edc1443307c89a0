// The balancing simulation: frame after frame, the balancer splits the rows, FrameSim plays the
// frame out, and the balancer hears what the farm would tell it.
#include "tools/balance-sim/balance_sim.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/base/work_unit.h"
#include "common/sampling/rng.h"
#include "tools/balance-sim/frame_sim.h"

namespace pathfarm::sim {
namespace {

double gaussian(Pcg32& rng) {  // Box-Muller
    const double u1 = std::max(1e-12, double(rng.next_float())), u2 = rng.next_float();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace

std::vector<FrameResult> simulate(coord::Balancer& balancer, const SimOptions& o,
                                  const CostTrace& trace) {
    std::vector<FrameResult> results;
    if (trace.empty()) return results;
    Pcg32 rng(o.seed);
    const int height = int(trace[0].size()) * kRowsPerWorkUnit;
    std::vector<coord::TracerFrame> last(o.speeds.size());
    std::vector<double> last_costs;
    for (int f = 0; f < o.frames; ++f) {
        const std::vector<double>& cost = trace[std::size_t(f) % trace.size()];
        const auto ranges = balancer.assign(coord::BalanceInput{height, last, last_costs});
        std::vector<double> speeds;
        double total_cost = 0.0, total_speed = 0.0;
        for (double c : cost)
            total_cost += c;
        for (double s : o.speeds) {
            const double hiccup = rng.next_float() < o.hiccup_p ? 0.5 : 1.0;
            speeds.push_back(s * std::exp(o.noise_sigma * gaussian(rng)) * hiccup);
            total_speed += speeds.back();
        }
        FrameSim frame(cost, speeds, o.latency_ms, o.units_per_tile, balancer.steals_mid_frame());
        frame.run(ranges);
        results.push_back({frame.frame_ms(), total_cost / total_speed, frame.strict_idle_pct(),
                           frame.farm_idle_pct()});
        last = frame.feedback(ranges, last_costs);
    }
    return results;
}

Result<CostTrace> read_cost_trace(const std::string& path) {
    std::ifstream in(path);
    if (!in) return make_error(ErrorCode::not_found, "--trace {}: cannot read", path);
    std::string line;
    std::getline(in, line);
    if (line.rfind("frame,unit,cost_us", 0) != 0)
        return make_error(ErrorCode::parse_error, "{}: expected the header frame,unit,cost_us",
                          path);
    CostTrace trace;
    for (int n = 2; std::getline(in, line); ++n) {
        std::istringstream ls(line);
        long frame = -1, unit = -1;
        double cost = -1.0;
        char c1 = 0, c2 = 0;
        if (!(ls >> frame >> c1 >> unit >> c2 >> cost) || c1 != ',' || c2 != ',' || frame < 0 ||
            unit < 0 || cost < 0.0 || frame > 1000000 || unit > 100000)
            return make_error(ErrorCode::parse_error, "{}:{}: expected frame,unit,cost_us", path,
                              n);
        if (trace.size() <= std::size_t(frame)) trace.resize(std::size_t(frame) + 1);
        auto& row = trace[std::size_t(frame)];
        if (row.size() <= std::size_t(unit)) row.resize(std::size_t(unit) + 1, 0.0);
        row[std::size_t(unit)] = cost / 1000.0;
    }
    trace.erase(std::remove_if(trace.begin(), trace.end(), [](const auto& r) { return r.empty(); }),
                trace.end());
    if (trace.empty()) return make_error(ErrorCode::parse_error, "{}: no costs", path);
    const std::size_t units = trace[0].size();
    for (const auto& r : trace)
        if (r.size() != units)
            return make_error(ErrorCode::parse_error, "{}: frames have different unit counts",
                              path);
    return trace;
}

CostTrace generate_trace(int units, int frames, double drift, uint64_t seed) {
    Pcg32 rng(seed);
    CostTrace t(static_cast<std::size_t>(frames),
                std::vector<double>(static_cast<std::size_t>(units)));
    for (int f = 0; f < frames; ++f)
        for (int u = 0; u < units; ++u) {
            const double centre = std::fmod(f * drift, double(units));
            const double d = std::min(std::abs(u - centre), units - std::abs(u - centre));
            t[std::size_t(f)][std::size_t(u)] =
                1.0 + 4.0 * std::exp(-d * d / 30.0) + 0.2 * rng.next_float();
        }
    return t;
}

}  // namespace pathfarm::sim
