// The tracer daemon: connects (and reconnects with backoff) to a coordinator, keeps a replica
// of the scene from its snapshot and commits, renders the rows it is assigned with a backend
// and streams them back as tiles with their measured cost per 4-row work unit.
#pragma once

#include <atomic>
#include <string>

#include "common/base/result.h"

namespace pathfarm::tracer {

struct TracerOptions {
    std::string host = "127.0.0.1";
    uint16_t port = 0;
    std::string backend = "embree";
    int threads = 0;
    int cl_platform = 0;  // OpenCL backend: platform and device index
    int cl_device = 0;
    bool texture_lod = true;  // BackendOptions::texture_lod
    std::string secret;
    bool insecure_plaintext = false;  // the coordinator link in the clear (benchmarks only)
    std::string name = "tracer";
    double slowdown = 1.0;  // >1: wait (slowdown - 1) x the render time after each tile
    // Probability per frame that this tracer renders it twice as slowly (a hiccup: another job,
    // thermal throttling); drawn from (hiccup_seed, frame) so runs repeat. For benchmarks.
    double hiccup_p = 0.0;
    uint32_t hiccup_seed = 1;
    int max_reconnects = -1;  // -1: forever
};

// How many times slower than its real speed the tracer renders `frame` (slowdown and hiccups).
double frame_slowdown(const TracerOptions& o, uint64_t frame);

// Runs until `stop` becomes true (or the reconnect budget is spent). Returns an error for
// problems that retrying cannot fix (bad options, backend unavailable) and when the budget ran
// out on a coordinator it could not reach (the last attempt's reason, io_error); a session
// that ended with no reconnection left to try is success.
Status run_tracer(const TracerOptions& options, const std::atomic<bool>& stop);

}  // namespace pathfarm::tracer
