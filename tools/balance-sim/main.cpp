// pathfarm-balance-sim: Brigade's Table 1, and ours, on recorded or generated cost traces.
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include <CLI/CLI.hpp>

#include "common/cli/command_line.h"
#include "tools/balance-sim/sim_report.h"

int main(int argc, char** argv) {
    pathfarm::sim::ReportOptions o;
    std::string tracers = "2,3", cameras = "slow,fast", schemes = "all";
    CLI::App app{"pathfarm-balance-sim: simulate row balancing schemes on cost traces"};
    app.add_option("--tracers", tracers, "Tracer counts to simulate, comma separated")
        ->capture_default_str();
    app.add_option("--camera", cameras, "Camera paths: slow, fast (the shipped recorded traces)")
        ->capture_default_str();
    app.add_option("--frames", o.sim.frames, "Frames per run")->capture_default_str();
    app.add_option("--schemes", schemes,
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
    if (auto exit_code =
            pathfarm::parse_command_line(app, argc, argv, "pathfarm-balance-sim", "warn"))
        return *exit_code;
    auto split = [](const std::string& s) {
        std::vector<std::string> out;
        std::stringstream ss(s);
        for (std::string item; std::getline(ss, item, ',');)
            out.push_back(item);
        return out;
    };
    o.tracer_counts.clear();
    for (const std::string& t : split(tracers))
        o.tracer_counts.push_back(std::atoi(t.c_str()));
    o.cameras = split(cameras);
    o.schemes = schemes == "all" ? pathfarm::sim::all_schemes() : split(schemes);
    auto report = pathfarm::sim::run_report(o);
    if (!report) {
        std::fprintf(stderr, "pathfarm-balance-sim: %s\n", report.error().message.c_str());
        return report.error().code == pathfarm::ErrorCode::invalid_argument ? 2 : 1;
    }
    std::fputs(report->c_str(), stdout);
    return 0;
}
