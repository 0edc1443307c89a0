// Reducing a frame's unit reports (unit_costs.h).
#include "coordinator/balance/unit_costs.h"

#include <algorithm>
#include <map>

namespace pathfarm::coord {

std::vector<double> unit_cost_map(const std::vector<UnitReport>& units) {
    std::map<uint64_t, std::pair<double, double>> per_tracer;  // rays, us
    for (const UnitReport& u : units) {
        per_tracer[u.owner].first += u.rays;
        per_tracer[u.owner].second += u.us;
    }
    std::vector<double> cost(units.size());
    for (std::size_t k = 0; k < units.size(); ++k) {
        const auto& [rays, us] = per_tracer[units[k].owner];
        cost[k] = us > 0.0 ? units[k].us * rays / us : units[k].rays;
    }
    return cost;
}

int delivered_rows(const std::vector<UnitReport>& units, uint64_t owner, int height) {
    int rows = 0;
    for (std::size_t u = 0; u < units.size(); ++u)
        if (units[u].owner == owner)
            rows += std::min(height, int(u + 1) * kRowsPerWorkUnit) - int(u) * kRowsPerWorkUnit;
    return rows;
}

double delivered_cost(const std::vector<UnitReport>& units, const std::vector<double>& cost,
                      uint64_t owner) {
    double sum = 0.0;
    for (std::size_t u = 0; u < units.size() && u < cost.size(); ++u)
        if (units[u].owner == owner) sum += cost[u];
    return sum;
}

TracerFrame tracer_feedback(const RowRange& first_range, double render_ms, double cost_delivered) {
    return TracerFrame{first_range, render_ms, render_ms > 0.0 ? cost_delivered / render_ms : 0.0};
}

double idle_percent(const std::vector<double>& busy_ms) {
    if (busy_ms.empty()) return 0.0;
    const double t_max = *std::max_element(busy_ms.begin(), busy_ms.end());
    if (!(t_max > 0.0)) return 0.0;
    double idle = 0.0;
    for (double b : busy_ms)
        idle += t_max - b;
    return 100.0 * idle / (double(busy_ms.size()) * t_max);
}

}  // namespace pathfarm::coord
