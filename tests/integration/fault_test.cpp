// Faults on the links, injected by a TCP proxy (tests/support/fault_proxy.h) between the
// coordinator and a tracer or a client: a reset in the middle of a message, a stall, a
// half-open connection, latency with a bandwidth cap. Frames keep coming, every frame is
// delivered and equals pathfarm-render's bit for bit (no frame assembled from stale or lost
// rows), the tracer reconnects, the client reconnects.
#include <csignal>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "tests/support/farm_harness.h"
#include "tests/support/process.h"
#include "tools/fault-proxy/fault_proxy.h"

namespace pathfarm {
namespace {

using namespace std::chrono_literals;
using test::Farm;
using test::kClient;
using test::Process;
using tools::FaultProxy;
using Direction = FaultProxy::Direction;

// Every frame was shown, and each equals pathfarm-render's.
void expect_all_frames_exact(Farm& farm, int frames) {
    ASSERT_EQ(farm.csv("stats.csv").size(), std::size_t(frames)) << "no frame lost";
    for (int f = 0; f < frames; ++f)
        EXPECT_TRUE(test::images_identical(farm.frame(f), farm.reference(f))) << "frame " << f;
}

void wait_until(const std::function<bool()>& done, std::chrono::milliseconds limit) {
    for (auto waited = 0ms; waited < limit && !done(); waited += 20ms)
        std::this_thread::sleep_for(20ms);
}

// The farm of these tests: a steady tracer on the coordinator's port, a second one behind
// the proxy, frames slow enough (slowdown) that faults land mid-frame.
struct FaultyFarm {
    Farm farm;
    std::unique_ptr<FaultProxy> proxy;
    explicit FaultyFarm(int frames, std::vector<std::string> extra = {}) {
        std::vector<std::string> args{"--frames", std::to_string(frames), "--min-tracers",
                                      "2",        "--deadline-ms",        "1500"};
        args.insert(args.end(), extra.begin(), extra.end());
        farm.start(args);
        proxy = std::make_unique<FaultProxy>(uint16_t(farm.tracer_port));
        farm.add_tracer("steady", {"--slowdown", "8", "--max-reconnects", "0"});
        farm.add_tracer("proxied", {"--slowdown", "8"}, proxy->port());  // reconnects forever
    }
    int shown() const { return int(farm.csv("stats.csv").size()); }
};

TEST(LinkFaults, TracerLinkResetMidMessageIsSurvivedAndTheTracerReconnects) {
    FaultyFarm f(8);
    wait_until([&] { return f.shown() >= 2; }, 30s);
    // 3000 bytes into the tracer's next tile: the tile is cut in the middle and the line reset.
    f.proxy->reset_after(3000, Direction::to_target);
    ASSERT_EQ(f.farm.finish(), 0);
    expect_all_frames_exact(f.farm, 8);
    EXPECT_GE(f.proxy->connections(), 2) << "the tracer reconnected";
}

TEST(LinkFaults, AStalledTracerLinkDelaysNoFrameForever) {
    FaultyFarm f(8);
    wait_until([&] { return f.shown() >= 2; }, 30s);
    f.proxy->stall(4s);  // past the 1.5 s deadline: its rows are re-issued
    ASSERT_EQ(f.farm.finish(), 0);
    expect_all_frames_exact(f.farm, 8);
}

TEST(LinkFaults, AHalfOpenTracerIsGivenUpAndFramesKeepComing) {
    FaultyFarm f(10);
    wait_until([&] { return f.shown() >= 2; }, 30s);
    f.proxy->half_open();  // no FIN, no RST: only silence tells
    ASSERT_EQ(f.farm.finish(std::chrono::seconds(90)), 0);
    expect_all_frames_exact(f.farm, 10);
    // It is given up at the first deadline it misses, not waited for in every later frame.
    const std::string log = test::read_file(f.farm.dir + "/coordinator.log");
    EXPECT_NE(log.find("\"proxied\" sent nothing for 1500 ms; disconnecting it"), std::string::npos)
        << log;
    int misses = 0;
    for (auto at = log.find("missed the"); at != std::string::npos;
         at = log.find("missed the", at + 1))
        ++misses;
    EXPECT_LE(misses, 2) << log;
}

TEST(LinkFaults, LatencyAndABandwidthCapChangeNoPixel) {
    FaultyFarm f(4);
    f.proxy->set_latency(30ms);
    f.proxy->set_bandwidth(2 << 20);  // 2 MiB/s: a snapshot takes a while
    ASSERT_EQ(f.farm.finish(), 0);
    expect_all_frames_exact(f.farm, 4);
    EXPECT_GT(f.proxy->forwarded(Direction::from_target), 0u);
}

TEST(LinkFaults, TheClientReconnectsAfterItsLinkIsReset) {
    Farm farm;
    farm.start({"--frames", "30"});
    FaultProxy proxy(uint16_t(farm.client_port));
    Process client({kClient, "--connect", "127.0.0.1:" + std::to_string(proxy.port()), "--headless",
                    "--frames", "12", "--out", farm.dir + "/received"},
                   farm.dir + "/client.log");
    farm.add_tracer("t", {"--slowdown", "8", "--max-reconnects", "0"});
    wait_until([&] { return farm.csv("stats.csv").size() >= 3; }, 30s);
    proxy.reset_after(100, Direction::from_target);  // in the middle of the next frame
    EXPECT_EQ(client.wait(60s), std::optional<int>(0)) << test::read_file(farm.dir + "/client.log");
    farm.coordinator->kill(SIGTERM);
    farm.finish();
    EXPECT_GE(proxy.connections(), 2) << test::read_file(farm.dir + "/client.log");
    EXPECT_NE(test::read_file(farm.dir + "/client.log").find("frames=12"), std::string::npos)
        << test::read_file(farm.dir + "/client.log");
}

TEST(LinkFaults, TheClientReconnectsWhenItsLinkGoesSilent) {
    Farm farm;
    farm.start({"--frames", "40"});
    FaultProxy proxy(uint16_t(farm.client_port));
    Process client({kClient, "--connect", "127.0.0.1:" + std::to_string(proxy.port()), "--headless",
                    "--frames", "12", "--silence-seconds", "1", "--out", farm.dir + "/received"},
                   farm.dir + "/client.log");
    farm.add_tracer("t", {"--slowdown", "8", "--max-reconnects", "0"});
    wait_until([&] { return farm.csv("stats.csv").size() >= 3; }, 30s);
    proxy.half_open();  // frames stop arriving; no FIN, no RST
    EXPECT_EQ(client.wait(60s), std::optional<int>(0)) << test::read_file(farm.dir + "/client.log");
    farm.coordinator->kill(SIGTERM);
    farm.finish();
    const std::string log = test::read_file(farm.dir + "/client.log");
    EXPECT_NE(log.find("no frame for 1 s; reconnecting"), std::string::npos) << log;
    EXPECT_NE(log.find("frames=12"), std::string::npos) << log;
}

// Real time: the only tracer dies in the middle of a frame and another joins later. The frame
// is not skipped: the newcomer gets a snapshot of it and its missing rows.
TEST(LinkFaults, AFrameWhoseEveryTracerLeftIsTakenOverNotLost) {
    Farm farm;
    farm.mode = {"--game",        "free-camera", "--target-fps", "10",
                 "--no-converge", "--denoise",   "off"};
    farm.start({"--frames", "12"});
    Process& doomed = farm.add_tracer("doomed", {"--slowdown", "40", "--max-reconnects", "0"});
    wait_until([&] { return farm.csv("stats.csv").size() >= 3; }, 30s);
    std::this_thread::sleep_for(50ms);  // inside the next frame's rows
    doomed.kill(SIGKILL);
    std::this_thread::sleep_for(300ms);
    farm.add_tracer("rescuer", {"--max-reconnects", "0"});
    ASSERT_EQ(farm.finish(), 0);
    const auto rows = farm.csv("stats.csv");
    ASSERT_EQ(rows.size(), 12u) << "no frame lost";
    for (std::size_t f = 0; f < rows.size(); ++f)
        EXPECT_EQ(rows[f].at(0), std::to_string(f));
    const std::string log = test::read_file(farm.dir + "/coordinator.log");
    EXPECT_EQ(log.find("continuing with the next"), std::string::npos) << log;
}

}  // namespace
}  // namespace pathfarm
