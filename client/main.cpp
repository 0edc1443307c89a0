// pathfarm-client command line: the SDL2 window, or --headless.
#include <cmath>
#include <csignal>
#include <cstdio>
#include <utility>

#include <CLI/CLI.hpp>

#include "client/client.h"
#include "common/cli/command_line.h"
#include "common/net/auth.h"

namespace {

std::atomic<bool> g_stop{false};
void request_stop(int) { g_stop = true; }

struct CommandLine {
    pathfarm::client::ClientOptions options;
    std::string connect, secret_file, format = "jpeg";
    bool headless = false;
};

void add_options(CLI::App& app, CommandLine& c) {
    pathfarm::client::ClientOptions& o = c.options;
    app.add_option("--connect", c.connect, "Coordinator client port, HOST:PORT")->required();
    app.add_option("--secret-file", c.secret_file,
                   "File holding the shared secret (else $PATHFARM_SECRET)");
    app.add_flag(
        "--insecure-plaintext", o.insecure_plaintext,
        "Benchmarks only: no TLS on the coordinator link (commits, tiles and frames in the "
        "clear); the other end must say so too");
    app.add_option("--reconnect-seconds", o.reconnect_seconds,
                   "Retry a lost link (reset, cut TLS stream, silence) for this long; 0: never")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 3600.0));
    app.add_option("--silence-seconds", o.silence_seconds,
                   "No frame for this long after frames came: the link is lost (0: never)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 3600.0));
    app.add_flag("--headless", c.headless,
                 "No window: write frames to --out (default: a window with WASD + mouse look, "
                 "E for action, Esc to quit)");
    app.add_option("--frames", o.frames,
                   "Stop after this many frames (0: until the coordinator closes)")
        ->capture_default_str();
    app.add_option("--out", o.out_dir, "Folder for received frames");
    app.add_option("--format", c.format,
                   "Frame format to request and write: jpeg, png, exr (lossless linear float) "
                   "or h264 (the stream, written as stream.h264)")
        ->capture_default_str()
        ->check(CLI::IsMember({"jpeg", "png", "exr", "h264"}));
    app.add_option("--latency-csv", o.latency_csv,
                   "Per frame: frame,arrival_ms,interval_ms,inputs_acked,latency_ms");
    app.add_option("--turn-rate", o.turn_rate,
                   "Headless: a scripted player turning at this many rad/s (input for latency)")
        ->capture_default_str();
    app.add_flag("--action-every-second", o.action_each_second,
                 "Headless: press the action key once a second");
    app.add_option("--screenshot", o.screenshot, "Window: PNG of the window at --screenshot-frame");
    app.add_option("--screenshot-frame", o.screenshot_frame, "Frame for --screenshot")
        ->capture_default_str();
    app.add_option("--script", o.script, "Camera script: lines of FRAME eye_xyz target_xyz");
    app.add_option("--contact-sheet", o.contact_sheet,
                   "PNG with thumbnails of up to 16 evenly spaced frames");
}

// The options the parser cannot check alone: the endpoint and the secret.
pathfarm::Status finish_options(CommandLine& c) {
    pathfarm::client::ClientOptions& o = c.options;
    o.window = !c.headless;
    auto endpoint = pathfarm::parse_endpoint("--connect", c.connect);
    if (!endpoint) return endpoint.error();
    // Taken silently before: a NaN or infinite turn rate (the coordinator drops non-finite
    // input, so the scripted player stood still) and negative frame counts.
    if (!std::isfinite(o.turn_rate))
        return pathfarm::make_error(pathfarm::ErrorCode::invalid_argument,
                                    "--turn-rate {}: must be finite", o.turn_rate);
    // CLI11's range lets NaN through (every comparison with it is false): a NaN silence
    // never detected a lost link.
    for (const auto& [flag, value] : {std::pair{"--reconnect-seconds", o.reconnect_seconds},
                                      std::pair{"--silence-seconds", o.silence_seconds}})
        if (!std::isfinite(value))
            return pathfarm::make_error(pathfarm::ErrorCode::invalid_argument,
                                        "{} {}: must be finite", flag, value);
    for (const auto& [flag, value] :
         {std::pair{"--frames", o.frames}, std::pair{"--screenshot-frame", o.screenshot_frame}})
        if (value < 0)
            return pathfarm::make_error(pathfarm::ErrorCode::invalid_argument,
                                        "{} {}: must be >= 0", flag, value);
    o.host = endpoint->host;
    o.port = endpoint->port;
    o.format = c.format == "exr"    ? pathfarm::client::OutputFormat::exr
               : c.format == "png"  ? pathfarm::client::OutputFormat::png
               : c.format == "h264" ? pathfarm::client::OutputFormat::h264
                                    : pathfarm::client::OutputFormat::jpeg;
    auto secret = pathfarm::net::load_secret(c.secret_file);
    if (!secret) return secret.error();
    o.secret = *secret;
    return {};
}

}  // namespace

int main(int argc, char** argv) {
    CommandLine c;
    CLI::App app{"pathfarm-client: the thin game client of a pathfarm farm"};
    add_options(app, c);
    if (auto exit_code = pathfarm::parse_command_line(app, argc, argv, "pathfarm-client"))
        return *exit_code;
    if (auto s = finish_options(c); !s) {
        std::fprintf(stderr, "pathfarm-client: %s\n", s.error().message.c_str());
        return 2;
    }
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
    auto report = pathfarm::client::run_client(c.options, g_stop);
    if (!report) {
        std::fprintf(stderr, "pathfarm-client: %s\n", report.error().message.c_str());
        return report.error().code == pathfarm::ErrorCode::invalid_argument ||
                       report.error().code == pathfarm::ErrorCode::parse_error
                   ? 2
                   : 1;
    }
    const auto& l = report->latency;
    std::printf("frames=%d seconds=%.3f fps=%.2f\n", report->frames, report->seconds,
                report->fps());
    std::printf(
        "inputs=%zu latency_p50_ms=%.1f latency_p99_ms=%.1f interval_p50_ms=%.1f "
        "interval_p99_ms=%.1f\n",
        l.inputs, l.latency_p50_ms, l.latency_p99_ms, l.interval_p50_ms, l.interval_p99_ms);
    return 0;
}
