// The thin client: connects to a coordinator's client port, sends the player's input (from
// the SDL window, or scripted when headless), receives frames, shows or writes them, and
// measures input-to-frame latency and frame pacing.
#pragma once

#include <atomic>
#include <map>
#include <string>

#include "client/latency_stats.h"
#include "common/base/result.h"
#include "common/math/types.h"

namespace pathfarm::client {

enum class OutputFormat { jpeg, png, exr, h264 };

struct ClientOptions {
    std::string host = "127.0.0.1";
    uint16_t port = 0;
    std::string secret;
    bool insecure_plaintext = false;  // the coordinator link in the clear (benchmarks only)
    // A lost link (reset, cut TLS stream, silence) is retried for this long; 0: never. A
    // coordinator that closes the link cleanly ends the client.
    double reconnect_seconds = 10.0;
    double silence_seconds = 10.0;  // no frame for this long after frames came: lost
    bool window = false;            // SDL2 window with keyboard and mouse; else headless
    int frames = 0;                 // stop after this many frames (0: until the coordinator closes)
    std::string out_dir;            // empty: do not write frames
    OutputFormat format = OutputFormat::jpeg;
    std::string script;               // camera script file
    double turn_rate = 0.0;           // headless: a scripted player turning this many rad/s
    bool action_each_second = false;  // headless: press the action key once a second
    std::string contact_sheet;        // PNG of up to 16 evenly spaced frames; empty: none
    std::string latency_csv;          // per frame: arrival, interval, inputs answered, latency
    std::string screenshot;           // window: PNG of the window after `screenshot_frame` frames
    int screenshot_frame = 10;
};

struct ClientReport {
    int frames = 0;
    double seconds = 0.0;
    LatencySummary latency;
    double fps() const { return seconds > 0.0 ? frames / seconds : 0.0; }
};

// Camera script: one pose per line, "FRAME eye_x eye_y eye_z target_x target_y target_z";
// '#' starts a comment. The pose for frame k is sent when frame k-1 arrives.
Result<std::map<uint64_t, Mat4>> read_camera_script(const std::string& path);

Result<ClientReport> run_client(const ClientOptions& options, const std::atomic<bool>& stop);

}  // namespace pathfarm::client
