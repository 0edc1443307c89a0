// A farm of real processes on loopback for integration tests: a coordinator, tracers added
// at will, its logs and CSVs in a scratch folder.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "tests/support/process.h"

namespace pathfarm::test {

extern const std::string kCoordinator, kTracer, kClient, kRender;

struct Farm {
    std::string dir;
    std::unique_ptr<Process> coordinator;
    std::vector<std::unique_ptr<Process>> tracers;
    int tracer_port = 0, client_port = 0;
    // Appended to every coordinator's arguments. The default is the bit-exact batch mode (no
    // pacing, workload scaling, converging, denoising or game logic); real-time tests clear it.
    std::vector<std::string> mode = {"--fixed-spp", "--no-converge", "--denoise",
                                     "off",         "--game",        "free-camera"};
    int spp = 2;
    static constexpr int kWidth = 64, kHeight = 50;  // every farm's frame size
    std::string scene = "builtin:default";
    std::vector<std::string> render_args;  // appended to reference()'s pathfarm-render

    Farm();
    // Starts a 64x50 coordinator (`spp` samples per pixel) on builtin:default with `extra`
    // arguments.
    void start(std::vector<std::string> extra, int port = 0);
    // port: where the tracer connects (0: tracer_port; a fault proxy's port in front of it).
    Process& add_tracer(const std::string& name, std::vector<std::string> extra = {}, int port = 0);
    int finish(std::chrono::milliseconds timeout = std::chrono::seconds(60));
    std::string reference(int frame);  // pathfarm-render's frame, same size and spp
    std::string frame(int f) const;    // the coordinator's dumped frame
    // Rows of a CSV in `dir`, header skipped.
    std::vector<std::vector<std::string>> csv(const std::string& file) const;
};

int free_port();

}  // namespace pathfarm::test
