// pathfarm-client command line (headless mode).
#include <csignal>
#include <cstdio>

#include <CLI/CLI.hpp>

#include "client/client.h"
#include "common/cli/command_line.h"
#include "common/net/auth.h"

namespace {

std::atomic<bool> g_stop{false};
void request_stop(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
    pathfarm::client::ClientOptions o;
    std::string connect, secret_file, format = "png";
    bool headless = false;
    CLI::App app{"pathfarm-client: the thin game client of a pathfarm farm"};
    app.add_option("--connect", connect, "Coordinator client port, HOST:PORT")->required();
    app.add_option("--secret-file", secret_file,
                   "File holding the shared secret (else $PATHFARM_SECRET)");
    app.add_flag("--headless", headless, "No window: write frames to --out");
    app.add_option("--frames", o.frames,
                   "Stop after this many frames (0: until the coordinator closes)")
        ->capture_default_str();
    app.add_option("--out", o.out_dir, "Folder for received frames");
    app.add_option("--format", format,
                   "Frame format to request and write: png or exr (lossless linear float)")
        ->capture_default_str()
        ->check(CLI::IsMember({"png", "exr"}));
    app.add_option("--script", o.script, "Camera script: lines of FRAME eye_xyz target_xyz");
    app.add_option("--contact-sheet", o.contact_sheet,
                   "PNG with thumbnails of up to 16 evenly spaced frames");
    if (auto exit_code = pathfarm::parse_command_line(app, argc, argv, "pathfarm-client"))
        return *exit_code;
    if (!headless) {
        std::fprintf(stderr,
                     "pathfarm-client: only --headless is available in this build (the window "
                     "comes with SDL2)\n");
        return 2;
    }
    const auto colon = connect.rfind(':');
    const int port = colon == std::string::npos ? 0 : std::atoi(connect.c_str() + colon + 1);
    if (port <= 0 || port > 65535) {
        std::fprintf(stderr, "pathfarm-client: --connect %s: expected HOST:PORT\n",
                     connect.c_str());
        return 2;
    }
    o.host = connect.substr(0, colon);
    o.port = uint16_t(port);
    o.format =
        format == "exr" ? pathfarm::client::OutputFormat::exr : pathfarm::client::OutputFormat::png;
    auto secret = pathfarm::net::load_secret(secret_file);
    if (!secret) {
        std::fprintf(stderr, "pathfarm-client: %s\n", secret.error().message.c_str());
        return 2;
    }
    o.secret = *secret;
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
    auto report = pathfarm::client::run_client(o, g_stop);
    if (!report) {
        std::fprintf(stderr, "pathfarm-client: %s\n", report.error().message.c_str());
        return report.error().code == pathfarm::ErrorCode::invalid_argument ||
                       report.error().code == pathfarm::ErrorCode::parse_error
                   ? 2
                   : 1;
    }
    std::printf("frames=%d seconds=%.3f fps=%.2f\n", report->frames, report->seconds,
                report->fps());
    return 0;
}
