// The thin client, headless part: connects to a coordinator's client port, sends scripted
// input, receives frames and writes them to files. The SDL window comes with the real-time
// issue.
#pragma once

#include <atomic>
#include <map>
#include <string>

#include "common/base/result.h"
#include "common/math/types.h"

namespace pathfarm::client {

enum class OutputFormat { png, exr };

struct ClientOptions {
    std::string host = "127.0.0.1";
    uint16_t port = 0;
    std::string secret;
    int frames = 0;       // stop after this many frames (0: until the coordinator closes)
    std::string out_dir;  // empty: do not write frames
    OutputFormat format = OutputFormat::png;
    std::string script;         // camera script file
    std::string contact_sheet;  // PNG of up to 16 evenly spaced frames; empty: none
};

struct ClientReport {
    int frames = 0;
    double seconds = 0.0;
    double fps() const { return seconds > 0.0 ? frames / seconds : 0.0; }
};

// Camera script: one pose per line, "FRAME eye_x eye_y eye_z target_x target_y target_z";
// '#' starts a comment. The pose for frame k is sent when frame k-1 arrives.
Result<std::map<uint64_t, Mat4>> read_camera_script(const std::string& path);

Result<ClientReport> run_client(const ClientOptions& options, const std::atomic<bool>& stop);

}  // namespace pathfarm::client
