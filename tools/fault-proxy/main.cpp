// pathfarm-fault-proxy: the fault proxy of the integration tests as a process, for the soak
// benchmark (bench/soak.sh) and by hand: relays 127.0.0.1:LISTEN to 127.0.0.1:TARGET with fixed
// latency and bandwidth, and with --random-faults injects a fault at random intervals: a
// stall, a reset in the middle of a message, a half-open connection, a latency change. One
// line per fault on stdout.
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <random>
#include <thread>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "common/cli/command_line.h"
#include "tools/fault-proxy/fault_proxy.h"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void request_stop(int) { g_stop = 1; }

using pathfarm::tools::FaultProxy;

// One random fault on the proxy's connections.
void inject(FaultProxy& proxy, std::mt19937& rng) {
    using namespace std::chrono;
    std::uniform_int_distribution<int> kind(0, 9);
    switch (kind(rng)) {
        case 0:
        case 1:
        case 2: {
            const auto d = milliseconds(std::uniform_int_distribution<int>(300, 3000)(rng));
            spdlog::info("fault: stall {} ms", d.count());
            proxy.stall(d);
            break;
        }
        case 3:
        case 4:
        case 5: {
            const uint64_t bytes = std::uniform_int_distribution<uint64_t>(0, 1 << 16)(rng);
            const auto dir =
                rng() % 2 ? FaultProxy::Direction::to_target : FaultProxy::Direction::from_target;
            spdlog::info("fault: reset after {} bytes {}", bytes,
                         dir == FaultProxy::Direction::to_target ? "to the target" : "back");
            proxy.reset_after(bytes, dir);
            break;
        }
        case 6: {
            spdlog::info("fault: half-open");
            proxy.half_open();
            break;
        }
        default: {
            const auto d = milliseconds(std::uniform_int_distribution<int>(0, 40)(rng));
            spdlog::info("fault: latency {} ms", d.count());
            proxy.set_latency(d);
        }
    }
}

// What CLI11's ranges let through, said on stderr. False: exit 2.
bool check_arguments(double every, int listen_port, int target_port) {
    if (!std::isfinite(every)) {  // passes CLI11's range check; drew a fault every 50 ms
        std::fprintf(stderr, "pathfarm-fault-proxy: --random-faults %g: must be in [0, 3600]\n",
                     every);
        return false;
    }
    if (target_port == listen_port) {  // every connection it accepted would open another
        std::fprintf(stderr,
                     "pathfarm-fault-proxy: --target %d: the proxy's own --listen port (it would "
                     "relay to itself)\n",
                     target_port);
        return false;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    int listen_port = 0, target_port = 0, latency_ms = 0, seed = 1;
    int64_t bandwidth = 0;  // signed, so that a negative value is refused, not wrapped
    double every = 0.0;
    CLI::App app{"pathfarm-fault-proxy: a TCP relay on loopback that injects faults"};
    app.add_option("--listen", listen_port, "Port to accept on (127.0.0.1)")
        ->required()
        ->check(CLI::Range(1, 65535));
    app.add_option("--target", target_port, "Port to relay to (127.0.0.1)")
        ->required()
        ->check(CLI::Range(1, 65535));
    app.add_option("--latency-ms", latency_ms, "Added one-way latency")
        ->capture_default_str()
        ->check(CLI::Range(0, 10000));
    app.add_option("--bandwidth", bandwidth, "Cap in bytes per second per direction (0: none)")
        ->capture_default_str()
        ->check(CLI::Range(int64_t(0), int64_t(1) << 40));
    app.add_option("--random-faults", every,
                   "Inject a random fault every S seconds on average (0: none)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 3600.0));
    app.add_option("--seed", seed, "Seed of the fault draws")->capture_default_str();
    if (auto exit_code = pathfarm::parse_command_line(app, argc, argv, "pathfarm-fault-proxy"))
        return *exit_code;
    if (!check_arguments(every, listen_port, target_port)) return 2;
    FaultProxy proxy{uint16_t(target_port), uint16_t(listen_port)};
    if (proxy.port() == 0) {
        std::fprintf(stderr, "pathfarm-fault-proxy: --listen %d: cannot listen there\n",
                     listen_port);
        return 1;
    }
    proxy.set_latency(std::chrono::milliseconds(latency_ms));
    proxy.set_bandwidth(uint64_t(bandwidth));
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
    spdlog::info("relaying 127.0.0.1:{} to 127.0.0.1:{}", proxy.port(), target_port);
    std::mt19937 rng{uint32_t(seed)};
    std::exponential_distribution<double> gap(every > 0.0 ? 1.0 / every : 1.0);
    auto next = std::chrono::steady_clock::now();
    if (every > 0.0)
        next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(gap(rng)));
    while (!g_stop) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        if (every <= 0.0 || std::chrono::steady_clock::now() < next) continue;
        inject(proxy, rng);
        next = std::chrono::steady_clock::now() +
               std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                   std::chrono::duration<double>(gap(rng)));
    }
    spdlog::info("stopped: {} connections", proxy.connections());
    return 0;
}
