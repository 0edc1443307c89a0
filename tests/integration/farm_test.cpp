// The farm as users run it: real coordinator, tracer and client processes on loopback.
// Determinism: frames of farms of 1, 2 and 3 tracers equal pathfarm-render bit for bit.
// Faults: a killed tracer's rows are re-assigned, a late tracer renders within 3 frames,
// tracers reconnect to a restarted coordinator, a departing client disturbs nothing.
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "common/film/image_compare.h"
#include "common/film/image_io.h"
#include "common/film/jpeg_codec.h"
#include "tests/support/farm_harness.h"
#include "tests/support/process.h"
#include "tests/support/test_env.h"
#include "tracer-node/tracer_daemon.h"

namespace pathfarm {
namespace {

using namespace std::chrono_literals;
using test::Farm;
using test::free_port;
using test::kClient;
using test::kCoordinator;
using test::kRender;
using test::kTracer;
using test::Process;

class FarmDeterminism : public ::testing::TestWithParam<int> {};

TEST_P(FarmDeterminism, FramesEqualPathfarmRenderBitForBit) {
    const int tracers = GetParam();
    Farm farm;
    farm.start({"--frames", "3", "--min-tracers", std::to_string(tracers)});
    for (int t = 0; t < tracers; ++t)
        farm.add_tracer("t" + std::to_string(t), {"--max-reconnects", "0"});
    ASSERT_EQ(farm.finish(), 0);
    for (int f : {0, 2})
        EXPECT_TRUE(test::images_identical(farm.frame(f), farm.reference(f)))
            << tracers << " tracers, frame " << f;
    // Every tracer took part and every frame's rows were all delivered. A tracer may render
    // nothing in a frame: on a loaded machine the others can take all its rows before it starts.
    std::set<std::string> names;
    std::map<int, int> delivered;
    for (const auto& row : farm.csv("tracers.csv")) {
        names.insert(row.at(1));
        delivered[std::stoi(row.at(0))] += std::stoi(row.at(5));
    }
    EXPECT_EQ(names.size(), std::size_t(tracers));
    for (int f = 0; f < 3; ++f)
        EXPECT_EQ(delivered[f], Farm::kHeight) << "frame " << f;
}

INSTANTIATE_TEST_SUITE_P(Tracers, FarmDeterminism, ::testing::Values(1, 2, 3));

// The coordinator's --light-sampler reaches the tracers (FrameAssignment.light_sampling): the
// farm's frame equals pathfarm-render's with the same sampler, and differs from the other
// sampler's. The default, auto, is what the determinism tests above run: each tracer resolves
// it from its replica's state, to the tree on builtin:default (LightSamplerChoice.*).
TEST(FarmLightSampler, TheCoordinatorsChoiceReachesTheTracers) {
    Farm farm;
    farm.start({"--frames", "1", "--light-sampler", "power"});
    farm.add_tracer("t", {"--max-reconnects", "0"});
    ASSERT_EQ(farm.finish(), 0);
    farm.render_args = {"--light-sampler", "tree"};
    const std::string tree = farm.reference(0);
    std::rename(tree.c_str(), (farm.dir + "/tree.pfm").c_str());
    farm.render_args = {"--light-sampler", "power"};
    EXPECT_TRUE(test::images_identical(farm.frame(0), farm.reference(0)));
    EXPECT_FALSE(test::images_identical(farm.frame(0), farm.dir + "/tree.pfm"));
}

// A file without a camera is framed from its bounds by the coordinator exactly as
// pathfarm-render frames it (the farm used to render it from the origin).
TEST(FarmFraming, SceneWithoutACameraIsFramedLikePathfarmRender) {
    Farm farm;
    farm.scene = farm.dir + "/no_camera.obj";
    std::ofstream(farm.dir + "/no_camera.mtl") << "newmtl white\nKd 0.7 0.7 0.7\n"
                                               << "newmtl lamp\nKd 0 0 0\nKe 8 8 8\n";
    std::ofstream(farm.scene) << "mtllib no_camera.mtl\n"
                                 "v -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\n"  // floor
                                 "v -0.5 0 -0.5\nv 0.5 0 -0.5\nv 0 1.2 0\n"  // a tent
                                 "v -0.4 2 -0.4\nv 0.4 2 -0.4\nv 0.4 2 0.4\nv -0.4 2 0.4\n"
                                 "usemtl white\nf 1 3 2\nf 1 4 3\nf 5 6 7\n"
                                 "usemtl lamp\nf 8 9 10\nf 8 10 11\n";
    farm.start({"--frames", "1"});
    farm.add_tracer("t", {"--max-reconnects", "0"});
    ASSERT_EQ(farm.finish(), 0);
    EXPECT_TRUE(test::images_identical(farm.frame(0), farm.reference(0)));
}

TEST(FarmFaults, KilledTracersRowsAreReassignedAndTheFrameCompletes) {
    Farm farm;
    // No stealing: the doomed tracer must still own unrendered rows when it dies.
    farm.start(
        {"--frames", "4", "--min-tracers", "2", "--deadline-ms", "60000", "--balancer", "none"});
    farm.add_tracer("steady", {"--max-reconnects", "0"});
    Process& doomed = farm.add_tracer("doomed", {"--slowdown", "400", "--max-reconnects", "0"});
    ASSERT_TRUE(test::wait_for_text(farm.dir + "/coordinator.log", "\"doomed\" connected", 10s));
    std::this_thread::sleep_for(1500ms);  // it is deep in its first tile of frame 0 now
    doomed.kill(SIGKILL);
    ASSERT_EQ(farm.finish(), 0);
    EXPECT_NE(test::read_file(farm.dir + "/coordinator.log").find("\"doomed\" left"),
              std::string::npos);
    EXPECT_EQ(farm.csv("stats.csv").size(), 4u) << "no frame lost";
    EXPECT_TRUE(test::images_identical(farm.frame(0), farm.reference(0)))
        << "re-issued rows render identically";
}

// A tracer 400 times slower keeps at most what it rendered before the fast one took its rows
// (it sent no tile, so it is taken to be on its first unit), stops where its rows were cut
// instead of rendering them again, and the frame is unchanged.
TEST(FarmBalance, IdleTracerTakesTheSlowTracersRowsAndTheSlowOneStopsThere) {
    Farm farm;
    farm.start({"--frames", "1", "--min-tracers", "2", "--balancer", "cost-predictive"});
    farm.add_tracer("fast", {"--max-reconnects", "0"});
    farm.add_tracer("slow", {"--slowdown", "400", "--max-reconnects", "0"});
    ASSERT_EQ(farm.finish(), 0);
    EXPECT_TRUE(test::images_identical(farm.frame(0), farm.reference(0)));
    int fast_assigned = -1, fast_delivered = 0, total = 0;
    for (const auto& row : farm.csv("tracers.csv")) {
        total += std::stoi(row.at(5));
        if (row.at(1) == "fast") {
            fast_assigned = std::stoi(row.at(3));
            fast_delivered = std::stoi(row.at(5));
        } else {
            EXPECT_LE(std::stoi(row.at(5)), std::stoi(row.at(3)) / 2) << "it stopped at the cut";
        }
    }
    ASSERT_GE(fast_assigned, 0) << "the fast tracer rendered";
    const int slow_assigned = 50 - fast_assigned;
    EXPECT_GE(slow_assigned, 20) << "the first frame splits the 50 rows about evenly";
    EXPECT_GE(fast_delivered, fast_assigned + slow_assigned / 2) << "it took the slow one's rows";
    EXPECT_EQ(total, 50) << "every row delivered once";
}

TEST(FarmFaults, LateTracerRendersWithinThreeFrames) {
    Farm farm;
    farm.start({"--frames", "14", "--min-tracers", "1"});
    farm.add_tracer("first", {"--slowdown", "40", "--max-reconnects", "0"});  // ~0.1 s a frame
    ASSERT_TRUE(test::wait_for_text(farm.dir + "/stats.csv", "\n3,", 30s));
    const std::size_t joined_at = farm.csv("stats.csv").size();
    farm.add_tracer("late", {"--max-reconnects", "0"});
    ASSERT_EQ(farm.finish(), 0);
    int first_late = -1;
    for (const auto& row : farm.csv("tracers.csv"))
        if (row.at(1) == "late" && first_late < 0) first_late = std::stoi(row.at(0));
    ASSERT_GE(first_late, 0) << "the late tracer never rendered";
    EXPECT_LE(first_late, int(joined_at) + 3) << "joined while frame ~" << joined_at << " rendered";
}

TEST(FarmFaults, TracersReconnectToARestartedCoordinator) {
    const int port = free_port();
    Farm farm;
    farm.start({"--frames", "2"}, port);
    Process& tracer = farm.add_tracer("persistent");  // reconnects forever
    ASSERT_EQ(farm.finish(), 0);
    farm.start({"--frames", "2"}, port);  // a new coordinator on the same port
    ASSERT_EQ(farm.finish(), 0) << "the tracer came back on its own";
    EXPECT_NE(test::read_file(tracer.log_path()).find("retrying"), std::string::npos);
}

TEST(FarmFaults, ClientLeavingMidStreamDisturbsNothing) {
    Farm farm;
    farm.start({"--frames", "8"});
    Process client(
        {kClient, "--connect", "127.0.0.1:" + std::to_string(farm.client_port), "--headless",
         "--frames", "2", "--out", farm.dir + "/received", "--format", "exr"},
        farm.dir + "/client.log");
    ASSERT_TRUE(
        test::wait_for_text(farm.dir + "/coordinator.log", "\"headless-client\" connected", 10s));
    farm.add_tracer("t", {"--slowdown", "10", "--max-reconnects", "0"});
    EXPECT_EQ(client.wait(30s), std::optional<int>(0)) << test::read_file(farm.dir + "/client.log");
    ASSERT_EQ(farm.finish(), 0);
    EXPECT_EQ(farm.csv("stats.csv").size(), 8u);
    EXPECT_NE(test::read_file(farm.dir + "/client.log").find("frames=2"), std::string::npos);
    EXPECT_TRUE(test::images_identical(farm.dir + "/received/frame_000001.exr", farm.reference(1)))
        << "lossless frames reach the client exactly";
}

// A native client may take the H.264 stream (the browsers' one): it decodes every frame, and
// what it shows is the JPEG client's picture within a codec's error. One H.264 client watches
// from the start, so the stream is running when a second joins mid-stream: the late one's
// first picture must be an IDR frame made for it (a delta frame would not decode to the
// picture).
TEST(FarmClients, H264AndJpegClientsSeeTheSameFrames) {
    Farm farm;
    farm.start({"--frames", "16"});
    const auto client = [&](const std::string& name, const std::string& format,
                            const std::string& frames) {
        return std::make_unique<Process>(
            std::vector<std::string>{
                kClient, "--connect", "127.0.0.1:" + std::to_string(farm.client_port), "--headless",
                "--frames", frames, "--out", farm.dir + "/" + name, "--format", format},
            farm.dir + "/" + name + ".log");
    };
    auto jpeg = client("jpeg", "jpeg", "16");
    auto early = client("early", "h264", "16");
    const auto connected = [&] {  // both before frame 0 (no tracer yet: no frames)
        const std::string log = test::read_file(farm.dir + "/coordinator.log");
        const std::string line = "\"headless-client\" connected";
        const auto first = log.find(line);
        return first != std::string::npos && log.find(line, first + 1) != std::string::npos;
    };
    for (int wait = 0; wait < 500 && !connected(); ++wait)
        std::this_thread::sleep_for(20ms);
    ASSERT_TRUE(connected());
    farm.add_tracer("t", {"--slowdown", "5", "--max-reconnects", "0"});
    for (int wait = 0; wait < 300 && farm.csv("stats.csv").size() < 4; ++wait)
        std::this_thread::sleep_for(20ms);
    ASSERT_GE(farm.csv("stats.csv").size(), 4u);
    auto late = client("late", "h264", "6");
    for (auto* p : {&jpeg, &early, &late})
        EXPECT_EQ((*p)->wait(30s), std::optional<int>(0));
    ASSERT_EQ(farm.finish(), 0);
    for (const std::string name : {"early", "late"}) {
        const std::string log = test::read_file(farm.dir + "/" + name + ".log");
        EXPECT_EQ(log.find("H.264"), std::string::npos) << "no picture failed to decode\n" << log;
        const std::string stream = farm.dir + "/" + name + "/stream.h264";
        EXPECT_TRUE(std::filesystem::exists(stream) && std::filesystem::file_size(stream) > 0)
            << stream;
    }
    std::map<std::string, int> compared;
    for (int f = 0; f < 16; ++f) {
        const std::string frame = fmt::format("frame_{:06d}", f);
        const std::string jpg = farm.dir + "/jpeg/" + frame + ".jpg";
        for (const std::string name : {"early", "late"}) {
            const std::string png = farm.dir + "/" + name + "/" + frame + ".png";
            if (!std::filesystem::exists(png) || !std::filesystem::exists(jpg)) continue;
            const std::string a = test::read_file(png), b = test::read_file(jpg);
            auto shown =
                decode_rgba8(reinterpret_cast<const unsigned char*>(a.data()), a.size(), png);
            auto other = decode_jpeg(b);
            ASSERT_TRUE(shown && other);
            std::vector<uint8_t> rgb;
            for (std::size_t i = 0; i < shown->rgba.size(); ++i)
                if (i % 4 != 3) rgb.push_back(shown->rgba[i]);
            EXPECT_GT(psnr8(rgb, other->rgb), 30.0) << name << " " << frame;
            ++compared[name];
        }
    }
    EXPECT_EQ(compared["early"], 16);
    EXPECT_EQ(compared["late"], 6);
}

// Runs `argv` and expects it to exit with `code` within 10 s, its output holding `message`.
void expect_refused(const Farm& farm, const std::vector<std::string>& argv, int code,
                    const std::string& message) {
    std::string command;
    for (const std::string& a : argv)
        command += a + " ";
    Process p(argv, farm.dir + "/refused.log");
    EXPECT_EQ(p.wait(10s), std::optional<int>(code)) << command;
    const std::string log = test::read_file(farm.dir + "/refused.log");
    EXPECT_NE(log.find(message), std::string::npos) << command << ": " << log;
}

TEST(FarmCli, BadInputIsAOneLineError) {
    Farm farm;
    unsetenv("PATHFARM_SECRET");
    expect_refused(farm, {kCoordinator, "--scene", "builtin:default", "--tracer-port", "0"}, 2,
                   "no shared secret");
    expect_refused(farm, {kTracer, "--coordinator", "nowhere"}, 2, "nowhere");
    expect_refused(farm, {kClient, "--connect", "127.0.0.1:1"}, 2, "");
    setenv("PATHFARM_SECRET", "farm-test-secret", 1);
    const std::vector<std::string> tracer{kTracer, "--coordinator", "127.0.0.1:1"};
    const std::vector<std::string> client{kClient, "--headless", "--connect", "127.0.0.1:1"};
    const std::vector<std::string> coordinator{
        kCoordinator, "--scene", "builtin:default", "--tracer-port", "0", "--client-port", "0"};
    // Each with its exit code and what its one line must say. Taken before: an infinite
    // slowdown (the tracer slept forever after its first tile); a NaN turn rate (the client's
    // player stood still), negative frame counts and a NaN silence (a lost link never seen); a
    // frame wider than the wire carries (failed only when a tracer came), a negative
    // --min-tracers and an infinite --target-fps; output folders that cannot be made (an
    // uncaught exception ended the process).
    const std::string file = farm.dir + "/a-file";
    std::ofstream(file) << "x";
    struct Case {
        const std::vector<std::string>& process;
        std::vector<std::string> args;
        int code;
        std::string message;
    };
    const std::vector<Case> cases{
        {tracer, {"--hiccup-p", "1.5"}, 2, "--hiccup-p 1.5: must be in [0, 1]"},
        {tracer, {"--nice", "25"}, 2, "--nice: Value 25 not in range 0 to 19"},
        {tracer, {"--slowdown", "inf"}, 2, "--slowdown inf: must be in [1, 1000]"},
        {tracer, {"--slowdown", "nan"}, 2, "--slowdown nan: must be in [1, 1000]"},
        {tracer, {"--slowdown", "0.5"}, 2, "--slowdown 0.5: must be in [1, 1000]"},
        {tracer, {"--slowdown", "5000"}, 2, "--slowdown 5000: must be in [1, 1000]"},
        {client, {"--turn-rate", "nan"}, 2, "--turn-rate nan: must be finite"},
        {client, {"--turn-rate", "inf"}, 2, "--turn-rate inf: must be finite"},
        {client, {"--frames", "-3"}, 2, "--frames -3: must be >= 0"},
        {client, {"--screenshot-frame", "-1"}, 2, "--screenshot-frame -1: must be >= 0"},
        {client, {"--silence-seconds", "nan"}, 2, "--silence-seconds nan: must be finite"},
        {client, {"--out", file + "/x"}, 1, "--out " + file + "/x: cannot create the folder"},
        {coordinator, {"--width", "0"}, 2, "--width 0: must be 1..16384"},
        {coordinator, {"--height", "20000"}, 2, "--height 20000: must be 1..16384"},
        {coordinator, {"--spp", "0"}, 2, "--spp 0: must be positive"},
        {coordinator, {"--fps", "nan"}, 2, "--fps nan: must be positive"},
        {coordinator, {"--fps", "inf"}, 2, "--fps inf: must be finite"},
        {coordinator, {"--deadline-ms", "-5"}, 2, "--deadline-ms -5: must be positive"},
        {coordinator, {"--min-tracers", "-1"}, 2, "--min-tracers -1: must be >= 0"},
        {coordinator, {"--min-resolution", "2"}, 2, "--min-resolution 2: must be in (0, 1]"},
        {coordinator, {"--target-fps", "inf"}, 2, "--target-fps inf: must be >= 0 and finite"},
        {coordinator, {"--dump-frames", file}, 1, "--dump-frames " + file + ": "}};
    for (const Case& c : cases) {
        std::vector<std::string> argv = c.process;
        argv.insert(argv.end(), c.args.begin(), c.args.end());
        expect_refused(farm, argv, c.code, c.message);
    }
}

// A tracer that gives up on a coordinator it cannot reach fails with the last attempt's reason
// (a supervisor sees it); one whose coordinator finished, with no reconnection left to try,
// ends normally.
TEST(TracerDaemon, GivingUpOnAnUnreachableCoordinatorIsAFailureAFinishedSessionIsNot) {
    Farm farm;
    const std::string address = "127.0.0.1:" + std::to_string(free_port());  // no one listens
    Process unreachable({kTracer, "--coordinator", address, "--max-reconnects", "1"},
                        farm.dir + "/unreachable.log");
    EXPECT_EQ(unreachable.wait(20s), std::optional<int>(1));
    std::istringstream log(test::read_file(farm.dir + "/unreachable.log"));
    std::string line, last;
    int retrying = 0;
    while (std::getline(log, line))
        if (!line.empty()) {
            last = line;
            retrying += line.find("retrying") != std::string::npos;
        }
    EXPECT_EQ(last.rfind("pathfarm-tracer: " + address + ": ", 0), 0u) << last;
    EXPECT_NE(last.find("(gave up after 2 connection attempts)"), std::string::npos) << last;
    EXPECT_EQ(retrying, 1) << "the last attempt retries no more";

    farm.start({"--frames", "1", "--min-tracers", "1"});
    Process& tracer = farm.add_tracer("t", {"--max-reconnects", "0"});
    ASSERT_EQ(farm.finish(), 0);
    EXPECT_EQ(tracer.wait(20s), std::optional<int>(0)) << test::read_file(farm.dir + "/t.log");
}

// --nice lowers every thread of a rendering tracer, the render arena's and the network
// thread's included: Linux keeps a nice value per thread, so one set after a thread started
// would miss it.
TEST(TracerDaemon, NiceReachesEveryThreadOfARenderingTracer) {
    Farm farm;
    farm.start({"--frames", "100000", "--min-tracers", "1"});
    Process tracer({kTracer, "--coordinator", "127.0.0.1:" + std::to_string(farm.tracer_port),
                    "--name", "t", "--threads", "2", "--nice", "7"},
                   farm.dir + "/t.log");
    // Rendering has started (and with it the arena's worker) once frames come back.
    for (auto waited = 0ms; waited < 30s && farm.csv("tracers.csv").size() < 3; waited += 50ms)
        std::this_thread::sleep_for(50ms);
    ASSERT_GE(farm.csv("tracers.csv").size(), 3u) << test::read_file(farm.dir + "/t.log");
    std::map<std::string, int> nice_by_thread;  // "tid (name)" -> nice
    const std::string tasks = "/proc/" + std::to_string(tracer.pid()) + "/task";
    for (const auto& task : std::filesystem::directory_iterator(tasks)) {
        const std::string stat = test::read_file(task.path().string() + "/stat");
        const auto name_end = stat.rfind(')');
        ASSERT_NE(name_end, std::string::npos) << stat;
        std::istringstream fields(stat.substr(name_end + 2));  // from field 3, the state
        std::string field;
        for (int k = 3; k <= 19; ++k)
            fields >> field;  // field 19: nice
        nice_by_thread[task.path().filename().string() + " " +
                       stat.substr(stat.find('('), name_end - stat.find('(') + 1)] =
            std::stoi(field);
    }
    // The main thread, the network thread, the tile sender and the arena's worker at least.
    EXPECT_GE(nice_by_thread.size(), 4u);
    for (const auto& [thread, nice] : nice_by_thread)
        EXPECT_EQ(nice, 7) << thread;
    EXPECT_TRUE(test::wait_for_text(farm.dir + "/t.log", "running at nice 7", 1s).has_value());
}

// Injected hiccups (for live balancing benchmarks) repeat for a seed and hit the asked fraction.
TEST(TracerHiccups, FrameSlowdownIsSeededAndHitsTheRequestedFraction) {
    tracer::TracerOptions o;
    o.slowdown = 1.5;
    o.hiccup_p = 0.1;
    int doubled = 0;
    for (uint64_t f = 0; f < 10000; ++f) {
        const double s = tracer::frame_slowdown(o, f);
        ASSERT_TRUE(s == 1.5 || s == 3.0) << s;
        doubled += s == 3.0;
        ASSERT_EQ(s, tracer::frame_slowdown(o, f)) << "same seed and frame, same draw";
    }
    EXPECT_NEAR(doubled, 1000, 100);  // binomial sd 30
    tracer::TracerOptions other = o;
    other.hiccup_seed = 2;
    int differ = 0;
    for (uint64_t f = 0; f < 1000; ++f)
        differ += tracer::frame_slowdown(o, f) != tracer::frame_slowdown(other, f);
    EXPECT_GT(differ, 50) << "another seed draws other frames";
    o.hiccup_p = 0.0;
    for (uint64_t f = 0; f < 1000; ++f)
        ASSERT_EQ(tracer::frame_slowdown(o, f), 1.5);
}

}  // namespace
}  // namespace pathfarm
