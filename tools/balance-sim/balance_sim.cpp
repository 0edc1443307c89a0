// Discrete simulation of one frame at a time: each tracer works through its units in order;
// with re-issue, a tracer that runs out takes the last not-yet-started unit of the tracer with
// the most work left.
#include "tools/balance-sim/balance_sim.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/sampling/rng.h"

namespace pathfarm::sim {
namespace {

double gaussian(Pcg32& rng) {  // Box-Muller
    const double u1 = std::max(1e-12, double(rng.next_float())), u2 = rng.next_float();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

struct Worker {
    double speed = 1.0;      // effective this frame
    std::vector<int> queue;  // unit indices, front first
    std::size_t next = 0;    // first unit not yet started
    double clock = 0.0, busy = 0.0;
    double own_ms = 0.0;     // time spent on its own assignment (what it reports)
    double done_cost = 0.0;  // cost of every unit it rendered, its own and taken ones
    double work_ms = 0.0;    // time spent rendering them, without messages
    bool done = false;       // idle and nothing left to take
};

}  // namespace

std::vector<FrameResult> simulate(coord::Balancer& balancer, const SimOptions& o,
                                  const CostTrace& trace) {
    std::vector<FrameResult> results;
    if (trace.empty()) return results;
    Pcg32 rng(o.seed);
    const int units = int(trace[0].size());
    const int height = units * coord::kRowsPerWorkUnit;
    std::vector<coord::TracerFrame> last(o.speeds.size());
    std::vector<double> last_costs;
    for (int f = 0; f < o.frames; ++f) {
        const std::vector<double>& cost = trace[std::size_t(f) % trace.size()];
        const auto ranges = balancer.assign(coord::BalanceInput{height, last, last_costs});
        std::vector<Worker> w(o.speeds.size());
        double total_cost = 0.0, total_speed = 0.0;
        for (double c : cost)
            total_cost += c;
        for (std::size_t i = 0; i < w.size(); ++i) {
            const double hiccup = rng.next_float() < o.hiccup_p ? 0.5 : 1.0;
            w[i].speed = o.speeds[i] * std::exp(o.noise_sigma * gaussian(rng)) * hiccup;
            total_speed += w[i].speed;
            for (int u = ranges[i].y0 / coord::kRowsPerWorkUnit;
                 u * coord::kRowsPerWorkUnit < ranges[i].y1; ++u)
                w[i].queue.push_back(u);
            w[i].clock = w[i].busy = o.latency_ms;  // the assignment message
        }
        // Process units in time order: always advance the worker that is free earliest.
        for (;;) {
            std::size_t i = 0;
            bool any = false;
            for (std::size_t k = 0; k < w.size(); ++k) {
                const bool has = w[k].next < w[k].queue.size();
                const bool can_steal = o.reissue && !w[k].done;
                if ((has || can_steal) && (!any || w[k].clock < w[i].clock)) {
                    i = k;
                    any = true;
                }
            }
            if (!any) break;
            Worker& me = w[i];
            int unit = -1;
            bool stolen = false;
            if (me.next < me.queue.size()) {
                unit = me.queue[me.next++];
            } else {  // re-issue: the last not-yet-started unit of the tracer that will finish
                      // last, if this tracer would finish that unit sooner than its owner would
                std::size_t victim = i;
                double latest = me.clock;
                for (std::size_t k = 0; k < w.size(); ++k) {
                    if (k == i || w[k].next >= w[k].queue.size()) continue;
                    double end = w[k].clock;  // when tracer k would finish all it still holds
                    for (std::size_t q = w[k].next; q < w[k].queue.size(); ++q)
                        end += cost[std::size_t(w[k].queue[q])] / w[k].speed;
                    if (end > latest) {
                        latest = end;
                        victim = k;
                    }
                }
                const bool worth =
                    victim != i &&
                    me.clock + o.latency_ms + cost[std::size_t(w[victim].queue.back())] / me.speed <
                        latest;
                if (!worth) {  // nothing left that this tracer could finish sooner: it is done
                    me.done = true;
                    continue;
                }
                unit = w[victim].queue.back();
                w[victim].queue.pop_back();
                stolen = true;
            }
            const double t = cost[std::size_t(unit)] / me.speed + (stolen ? o.latency_ms : 0.0);
            me.clock += t;
            me.busy += t;
            me.done_cost += cost[std::size_t(unit)];
            me.work_ms += cost[std::size_t(unit)] / me.speed;
            if (!stolen) me.own_ms += t;
        }
        // Tile messages: one per units_per_tile units of each tracer.
        double t_max = 0.0;
        for (Worker& x : w) {
            const double tiles = std::ceil(double(x.queue.size()) / o.units_per_tile);
            x.clock += tiles * o.latency_ms;
            x.busy += tiles * o.latency_ms;
            t_max = std::max(t_max, x.clock);
        }
        double idle = 0.0;
        for (const Worker& x : w)
            idle += t_max - x.busy;
        results.push_back({t_max, total_cost / total_speed,
                           t_max > 0.0 ? 100.0 * idle / (double(w.size()) * t_max) : 0.0});
        for (std::size_t i = 0; i < w.size(); ++i)
            last[i] =
                coord::TracerFrame{ranges[i], ranges[i].empty() ? 0.0 : w[i].own_ms + o.latency_ms,
                                   w[i].work_ms > 0.0 ? w[i].done_cost / w[i].work_ms : 0.0};
        last_costs = cost;  // a speed-independent cost per unit, as the farm's rays are
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
