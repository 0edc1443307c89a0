// pathfarm-balance-sim: Brigade's Table 1, and ours, on recorded or generated cost traces.
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include <CLI/CLI.hpp>

#include "common/cli/command_line.h"
#include "tools/balance-sim/sim_report.h"

namespace {

struct CommandLine {
    pathfarm::sim::ReportOptions o;
    std::string tracers = "2,3", cameras = "slow,fast", schemes = "all";
};

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, ',');)
        out.push_back(item);
    return out;
}

void add_options(CLI::App& app, CommandLine& c) {
    pathfarm::sim::ReportOptions& o = c.o;
    app.add_option("--tracers", c.tracers, "Tracer counts to simulate, comma separated")
        ->capture_default_str();
    app.add_option("--camera", c.cameras, "Camera paths: slow, fast (the shipped recorded traces)")
        ->capture_default_str();
    app.add_option("--frames", o.sim.frames, "Frames per run")->capture_default_str();
    app.add_option("--schemes", c.schemes,
                   "all, or a comma-separated list of none,robin-hood,perfect,perfect-smooth,ours")
        ->capture_default_str();
    app.add_option(
        "--trace", o.trace,
        "A frame,unit,cost_us trace for every camera instead of the shipped ones, or generated");
    app.add_option("--traces-dir", o.traces_dir,
                   "Folder of the shipped traces (default: beside this tool's sources)")
        ->capture_default_str();
    app.add_option("--seed", o.sim.seed, "Seed of noise and hiccups")->capture_default_str();
    app.add_option("--noise", o.sim.noise_sigma, "Lognormal sigma of per-frame speed noise")
        ->capture_default_str();
    app.add_option("--speed-smoothing", o.speed_smoothing,
                   "ours: weight of the last frame in each tracer's smoothed speed (1: none)")
        ->capture_default_str()
        ->check(CLI::Range(0.01, 1.0));
    app.add_option("--hiccup", o.sim.hiccup_p,
                   "Probability that a tracer takes 2x as long in a frame")
        ->capture_default_str();
    app.add_option("--latency-ms", o.sim.latency_ms, "Latency per message")->capture_default_str();
    app.add_option("--speeds2", o.speeds2, "Relative speeds with 2 tracers")
        ->delimiter(',')
        ->capture_default_str();
    app.add_option("--speeds3", o.speeds3, "Relative speeds with 3 tracers")
        ->delimiter(',')
        ->capture_default_str();
    app.add_option("--csv", o.csv,
                   "CSV: tracers,camera,scheme,idle_pct,p50_frame_rel,p99_frame_rel");
    app.add_option("--plot", o.plot, "PNG: idle % per frame for each scheme");
}

pathfarm::Status finish_options(CommandLine& c) {
    c.o.tracer_counts.clear();
    for (const std::string& t : split(c.tracers)) {
        const int n = std::atoi(t.c_str());
        if (n < 1 || std::to_string(n) != t)
            return pathfarm::make_error(pathfarm::ErrorCode::invalid_argument,
                                        "--tracers {}: \"{}\" is not a tracer count", c.tracers, t);
        c.o.tracer_counts.push_back(n);
    }
    c.o.cameras = split(c.cameras);
    c.o.schemes = c.schemes == "all" ? pathfarm::sim::all_schemes() : split(c.schemes);
    return {};
}

}  // namespace

int main(int argc, char** argv) {
    CommandLine c;
    CLI::App app{"pathfarm-balance-sim: simulate row balancing schemes on cost traces"};
    add_options(app, c);
    if (auto exit_code =
            pathfarm::parse_command_line(app, argc, argv, "pathfarm-balance-sim", "warn"))
        return *exit_code;
    if (auto s = finish_options(c); !s) {
        std::fprintf(stderr, "pathfarm-balance-sim: %s\n", s.error().message.c_str());
        return 2;
    }
    const pathfarm::sim::ReportOptions& o = c.o;
    auto report = pathfarm::sim::run_report(o);
    if (!report) {
        std::fprintf(stderr, "pathfarm-balance-sim: %s\n", report.error().message.c_str());
        return report.error().code == pathfarm::ErrorCode::invalid_argument ? 2 : 1;
    }
    std::fputs(report->c_str(), stdout);
    return 0;
}
