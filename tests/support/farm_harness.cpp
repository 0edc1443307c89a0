// The farm harness.
#include "tests/support/farm_harness.h"

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "tests/support/test_env.h"

namespace pathfarm::test {

using namespace std::chrono_literals;

const std::string kCoordinator = PATHFARM_COORDINATOR_EXE;
const std::string kTracer = PATHFARM_TRACER_EXE;
const std::string kClient = PATHFARM_CLIENT_EXE;
const std::string kRender = PATHFARM_RENDER_EXE;

Farm::Farm() : dir(scratch_dir()) { setenv("PATHFARM_SECRET", "farm-test-secret", 1); }

void Farm::start(std::vector<std::string> extra, int port) {
    std::vector<std::string> args{kCoordinator,
                                  "--scene",
                                  scene,
                                  "--tracer-port",
                                  std::to_string(port),
                                  "--client-port",
                                  "0",
                                  "--width",
                                  std::to_string(kWidth),
                                  "--height",
                                  std::to_string(kHeight),
                                  "--spp",
                                  std::to_string(spp),
                                  "--dump-frames",
                                  dir + "/dump",
                                  "--stats-csv",
                                  dir + "/stats.csv",
                                  "--tracer-stats-csv",
                                  dir + "/tracers.csv"};
    args.insert(args.end(), mode.begin(), mode.end());
    args.insert(args.end(), extra.begin(), extra.end());
    coordinator = std::make_unique<Process>(args, dir + "/coordinator.log");
    const auto line = wait_for_text(dir + "/coordinator.log", "tracer_port=", 10s);
    ASSERT_TRUE(line.has_value()) << read_file(dir + "/coordinator.log");
    std::istringstream ls(*line);
    ls >> tracer_port;
    client_port = std::stoi(line->substr(line->find("client_port=") + 12));
}

Process& Farm::add_tracer(const std::string& name, std::vector<std::string> extra, int port) {
    std::vector<std::string> args{kTracer,
                                  "--coordinator",
                                  "127.0.0.1:" + std::to_string(port != 0 ? port : tracer_port),
                                  "--name",
                                  name,
                                  "--threads",
                                  "1"};
    args.insert(args.end(), extra.begin(), extra.end());
    tracers.push_back(std::make_unique<Process>(args, dir + "/" + name + ".log"));
    return *tracers.back();
}

int Farm::finish(std::chrono::milliseconds timeout) {
    const auto rc = coordinator->wait(timeout);
    EXPECT_TRUE(rc.has_value()) << "coordinator did not finish\n"
                                << read_file(dir + "/coordinator.log");
    return rc.value_or(-1);
}

std::string Farm::reference(int frame) {
    const std::string out = dir + "/reference_" + std::to_string(frame) + ".pfm";
    std::vector<std::string> args{kRender,
                                  "--scene",
                                  scene,
                                  "--width",
                                  std::to_string(kWidth),
                                  "--height",
                                  std::to_string(kHeight),
                                  "--spp",
                                  std::to_string(spp),
                                  "--frame",
                                  std::to_string(frame),
                                  "--out",
                                  out,
                                  "--log-level",
                                  "error"};
    args.insert(args.end(), render_args.begin(), render_args.end());
    Process render(args, dir + "/render.log");
    EXPECT_EQ(render.wait(30s), std::optional<int>(0)) << read_file(dir + "/render.log");
    return out;
}

std::string Farm::frame(int f) const {
    char name[32];
    std::snprintf(name, sizeof(name), "/dump/frame_%06d.pfm", f);
    return dir + name;
}

std::vector<std::vector<std::string>> Farm::csv(const std::string& file) const {
    std::vector<std::vector<std::string>> rows;
    std::ifstream in(dir + "/" + file);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
        std::vector<std::string> row;
        std::stringstream ls(line);
        std::string cell;
        while (std::getline(ls, cell, ','))
            row.push_back(cell);
        rows.push_back(row);
    }
    return rows;
}

int free_port() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr));
    socklen_t len = sizeof(addr);
    getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
    close(fd);
    return ntohs(addr.sin_port);
}

}  // namespace pathfarm::test
