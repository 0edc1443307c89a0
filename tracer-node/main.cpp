// pathfarm-tracer command line: the tracer daemon.
#include <sys/resource.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/base/memory.h"
#include "common/cli/command_line.h"
#include "common/net/auth.h"
#include "tracer-node/backend/backend_cli.h"
#include "tracer-node/tracer_daemon.h"

namespace {

std::atomic<bool> g_stop{false};
void request_stop(int) { g_stop = true; }

// --nice: called before any thread starts, since Linux keeps a nice value per thread and
// threads inherit their creator's (the render arena, the tile sender and the network thread
// alike). A process started nicer than asked stays so. False (said on stderr) on failure.
bool run_at_nice(int nice) {
    errno = 0;
    const int inherited = getpriority(PRIO_PROCESS, 0);  // -1 is also a valid value
    if (errno != 0 || nice <= inherited) return true;
    if (setpriority(PRIO_PROCESS, 0, nice) != 0) {
        std::fprintf(stderr, "pathfarm-tracer: --nice %d: %s\n", nice, std::strerror(errno));
        return false;
    }
    spdlog::info("running at nice {}: other work on this machine comes first", nice);
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    pathfarm::tracer::TracerOptions o;
    std::string coordinator, secret_file;
    CLI::App app{"pathfarm-tracer: renders the rows a pathfarm coordinator assigns it"};
    app.add_option("--coordinator", coordinator, "Coordinator tracer port, HOST:PORT")->required();
    pathfarm::tracer::add_backend_options(app, o.backend, o.threads, o.cl_platform, o.cl_device,
                                          o.texture_lod);
    app.add_option("--secret-file", secret_file,
                   "File holding the shared secret (else $PATHFARM_SECRET)");
    app.add_flag(
        "--insecure-plaintext", o.insecure_plaintext,
        "Benchmarks only: no TLS on the coordinator link (commits, tiles and frames in the "
        "clear); the other end must say so too");
    app.add_option("--name", o.name, "Name shown in the coordinator's statistics")
        ->capture_default_str();
    app.add_option("--slowdown", o.slowdown,
                   "Run X times slower (waits (X-1) x render time), for tests")
        ->capture_default_str();
    app.add_option("--hiccup-p", o.hiccup_p,
                   "Probability per frame of rendering it 2x slower, for benchmarks")
        ->capture_default_str();
    app.add_option("--hiccup-seed", o.hiccup_seed, "Seed of the hiccup draws")
        ->capture_default_str();
    app.add_option("--max-reconnects", o.max_reconnects,
                   "Give up after this many failed connections (-1: never)")
        ->capture_default_str();
    int nice = 0;
    app.add_option("--nice", nice,
                   "Run at CPU nice value N (0-19; a process already nicer stays so): on a "
                   "machine shared with the coordinator, its display stage comes first")
        ->check(CLI::Range(0, 19))
        ->capture_default_str();
    if (auto exit_code = pathfarm::parse_command_line(app, argc, argv, "pathfarm-tracer"))
        return *exit_code;
    if (!run_at_nice(nice)) return 2;
    // Each frame allocates the buffers the last one freed: keep them mapped (memory.h).
    if (!pathfarm::keep_freed_memory()) spdlog::debug("the C library keeps its own malloc tuning");
    auto endpoint = pathfarm::parse_endpoint("--coordinator", coordinator);
    if (!endpoint) {
        std::fprintf(stderr, "pathfarm-tracer: %s\n", endpoint.error().message.c_str());
        return 2;
    }
    o.host = endpoint->host;
    o.port = endpoint->port;
    auto secret = pathfarm::net::load_secret(secret_file);
    if (!secret) {
        std::fprintf(stderr, "pathfarm-tracer: %s\n", secret.error().message.c_str());
        return 2;
    }
    o.secret = *secret;
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
    if (auto s = pathfarm::tracer::run_tracer(o, g_stop); !s) {
        std::fprintf(stderr, "pathfarm-tracer: %s\n", s.error().message.c_str());
        return s.error().code == pathfarm::ErrorCode::invalid_argument ? 2 : 1;
    }
    return 0;
}
