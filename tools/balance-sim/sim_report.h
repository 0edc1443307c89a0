// Runs the balancing simulation over tracer counts, camera traces and schemes, and reports
// Brigade-style tables (mean idle %), p50 / p99 frame time relative to ideal, CSV and a plot.
#pragma once

#include <string>
#include <vector>

#include "common/base/result.h"
#include "tools/balance-sim/balance_sim.h"

namespace pathfarm::sim {

struct ReportOptions {
    SimOptions sim;
    std::vector<int> tracer_counts{2, 3};
    std::vector<std::string> cameras{"slow", "fast"};
    std::vector<std::string> schemes;
    std::vector<double> speeds2{1.0, 0.6};
    std::vector<double> speeds3{1.0, 0.8, 0.5};
    std::string trace;  // overrides the shipped traces
    std::string traces_dir = PATHFARM_BALANCE_TRACES;
    std::string csv, plot;
    double speed_smoothing = coord::kDefaultSpeedSmoothing;  // ours, as the farm's option
};

// "ours" is the cost-predictive balancer plus its mid-frame steal (coordinator/balance/steal.h).
std::vector<std::string> all_schemes();
// The table as text; writes options.csv and options.plot when set.
Result<std::string> run_report(const ReportOptions& options);

}  // namespace pathfarm::sim
