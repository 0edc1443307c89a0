// Tables, CSV and plots of the balancing simulation.
#include "tools/balance-sim/sim_report.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string_view>
#include <utility>

#include <fmt/format.h>

namespace pathfarm::sim {
namespace {

struct Cell {
    double idle = 0.0, p50 = 0.0, p99 = 0.0;
    double farm_idle = 0.0;  // as the farm's stats would report it
    std::vector<double> idle_per_frame;
};
using Cells = std::map<std::string, std::map<std::string, Cell>>;  // column -> scheme -> cell

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

Result<Cell> run_cell(const ReportOptions& o, int tracers, const CostTrace& trace,
                      const std::string& scheme) {
    SimOptions sim = o.sim;
    sim.speeds = tracers == 2   ? o.speeds2
                 : tracers == 3 ? o.speeds3
                                : std::vector<double>(std::size_t(tracers), 1.0);
    if (int(sim.speeds.size()) != tracers)
        return make_error(ErrorCode::invalid_argument, "--speeds{}: {} speeds for {} tracers",
                          tracers, sim.speeds.size(), tracers);
    auto balancer = coord::make_balancer(scheme == "ours" ? "cost-predictive" : scheme, 0.25,
                                         o.speed_smoothing);
    if (!balancer)
        return make_error(ErrorCode::invalid_argument, "--schemes: unknown scheme \"{}\"", scheme);
    const auto frames = simulate(*balancer, sim, trace);
    Cell c;
    std::vector<double> rel;
    for (const FrameResult& f : frames) {
        c.idle += f.idle_pct / double(frames.size());
        c.farm_idle += f.farm_idle_pct / double(frames.size());
        c.idle_per_frame.push_back(f.idle_pct);
        rel.push_back(f.frame_ms / f.ideal_ms);
    }
    c.p50 = percentile(rel, 0.5);
    c.p99 = percentile(rel, 0.99);
    return c;
}

Status write_plot(const ReportOptions& o, const Cells& cells) {
    const std::string data = o.plot + ".frames.csv";
    std::ofstream out(data);
    out << "column,scheme,frame,idle_pct\n";
    for (const auto& [column, by_scheme] : cells)
        for (const auto& [scheme, cell] : by_scheme)
            for (std::size_t f = 0; f < cell.idle_per_frame.size(); ++f)
                out << column << ',' << scheme << ',' << f << ',' << cell.idle_per_frame[f] << '\n';
    out.close();
    std::string script = fmt::format(
        "set datafile separator ','\nset terminal pngcairo size 1400,900\nset output '{}'\n"
        "set multiplot layout 2,2\nset yrange [0:*]\nset xlabel 'frame'\nset ylabel 'idle %'\n",
        o.plot);
    for (const auto& [column, by_scheme] : cells) {
        script += fmt::format("set title 'idle % per frame: {}'\nplot ", column);
        bool first = true;
        for (const auto& [scheme, cell] : by_scheme) {
            script += fmt::format("{}'< grep \"^{},{},\" {}' using 3:4 with lines title '{}'",
                                  first ? "" : ", ", column, scheme, data, scheme);
            first = false;
        }
        script += "\n";
    }
    script += "unset multiplot\n";
    FILE* gp = popen("gnuplot", "w");
    if (gp == nullptr)
        return make_error(ErrorCode::io_error, "--plot {}: cannot run gnuplot", o.plot);
    std::fputs(script.c_str(), gp);
    if (pclose(gp) != 0)
        return make_error(ErrorCode::io_error, "--plot {}: gnuplot failed", o.plot);
    return {};
}

// One block of the table: `title`, then a row per scheme of `value(cell)` per column.
template <typename Value>
std::string table_block(const ReportOptions& o, const std::vector<std::string>& columns,
                        Cells& cells, const std::string& title, int width, Value value) {
    std::string block = fmt::format("{:<16}", title);
    for (const auto& c : columns)
        block += fmt::format("{:>{}}", c, width);
    block += "\n";
    for (const std::string& scheme : o.schemes) {
        block += fmt::format("{:<16}", scheme);
        for (const auto& c : columns)
            block += fmt::format("{:>{}}", value(cells[c][scheme]), width);
        block += "\n";
    }
    return block;
}

std::string format_table(const ReportOptions& o, const std::vector<std::string>& columns,
                         Cells& cells) {
    return table_block(o, columns, cells, "mean idle %", 10,
                       [](const Cell& c) { return fmt::format("{:.1f}", c.idle); }) +
           "\n" +
           table_block(o, columns, cells, "p50 / p99 frame", 14,
                       [](const Cell& c) { return fmt::format("{:.3f}/{:.3f}", c.p50, c.p99); }) +
           "\n" + table_block(o, columns, cells, "idle % (farm's)", 10, [](const Cell& c) {
               return fmt::format("{:.1f}", c.farm_idle);
           });
}

}  // namespace

std::vector<std::string> all_schemes() {
    return {"none", "robin-hood", "perfect", "perfect-smooth", "ours"};
}

namespace {

// The options a run needs in range: NaN, negative or zero values ran before and printed a
// table of zeros or NaN as if it were a result. Written as !(in range) so NaN fails too.
// The recorded trace shipped for a camera path.
std::string shipped_trace(const ReportOptions& o, const std::string& camera) {
    return o.traces_dir + "/" + camera + ".csv";
}

Status check_options(const ReportOptions& o) {
    const SimOptions& s = o.sim;
    const auto bad = [](std::string_view flag, double value, std::string_view range) {
        return make_error(ErrorCode::invalid_argument, "{} {}: must be {}", flag, value, range);
    };
    if (s.frames < 1) return bad("--frames", s.frames, ">= 1");
    if (!(s.noise_sigma >= 0.0 && s.noise_sigma <= 10.0))
        return bad("--noise", s.noise_sigma, "in [0, 10]");
    if (!(s.hiccup_p >= 0.0 && s.hiccup_p <= 1.0)) return bad("--hiccup", s.hiccup_p, "in [0, 1]");
    if (!(s.latency_ms >= 0.0 && s.latency_ms <= 1e6))
        return bad("--latency-ms", s.latency_ms, "in [0, 1e6]");
    if (!(o.speed_smoothing >= 0.01 && o.speed_smoothing <= 1.0))
        return bad("--speed-smoothing", o.speed_smoothing, "in [0.01, 1]");
    for (const auto& [flag, speeds] :
         {std::pair{"--speeds2", &o.speeds2}, {"--speeds3", &o.speeds3}})
        for (const double v : *speeds)
            if (!(v > 0.0 && v <= 1e6)) return bad(flag, v, "in (0, 1e6]");
    // Said as the missing trace file before, as if --trace had been given.
    if (o.trace.empty())
        for (const std::string& camera : o.cameras)
            if (!std::filesystem::is_regular_file(shipped_trace(o, camera)))
                return make_error(ErrorCode::invalid_argument,
                                  "--camera {}: no recorded trace {}.csv in --traces-dir {}",
                                  camera, camera, o.traces_dir);
    return {};
}

}  // namespace

Result<std::string> run_report(const ReportOptions& o) {
    if (Status s = check_options(o); !s) return s.error();
    Cells cells;
    std::vector<std::string> columns;
    std::ofstream csv;
    if (!o.csv.empty()) {
        csv.open(o.csv);
        if (!csv) return make_error(ErrorCode::io_error, "--csv {}: cannot write", o.csv);
        csv << "tracers,camera,scheme,idle_pct,p50_frame_rel,p99_frame_rel,farm_idle_pct\n";
    }
    for (int tracers : o.tracer_counts) {
        if (tracers < 1 || tracers > 64)
            return make_error(ErrorCode::invalid_argument, "--tracers {}: must be 1..64", tracers);
        for (const std::string& camera : o.cameras) {
            // "generated": a synthetic band drifting 0.3 (slow) or 3 (fast) units a frame.
            auto trace =
                o.trace == "generated"
                    ? Result<CostTrace>(generate_trace(45, o.sim.frames,
                                                       camera == "fast" ? 3.0 : 0.3, o.sim.seed))
                    : read_cost_trace(o.trace.empty() ? shipped_trace(o, camera) : o.trace);
            if (!trace) return trace.error();
            const std::string column = fmt::format("{} {}", tracers, camera);
            columns.push_back(column);
            for (const std::string& scheme : o.schemes) {
                auto cell = run_cell(o, tracers, *trace, scheme);
                if (!cell) return cell.error();
                if (csv.is_open())
                    csv << tracers << ',' << camera << ',' << scheme << ',' << cell->idle << ','
                        << cell->p50 << ',' << cell->p99 << ',' << cell->farm_idle << '\n';
                cells[column][scheme] = std::move(*cell);
            }
        }
    }
    std::string table = format_table(o, columns, cells);
    if (!o.plot.empty())
        if (Status s = write_plot(o, cells); !s) return s.error();
    return table;
}

}  // namespace pathfarm::sim
