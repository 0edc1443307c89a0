// Real child processes for integration tests: spawn with output to a log file, wait with a
// timeout, kill, and poll the log for a line.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace pathfarm::test {

class Process {
public:
    Process(const std::vector<std::string>& argv, const std::string& log_path);
    ~Process();  // kills the process if it still runs
    Process(const Process&) = delete;
    Process& operator=(const Process&) = delete;

    bool started() const { return pid_ > 0; }
    pid_t pid() const { return pid_; }
    // The exit code, or nullopt if it did not exit within the timeout (or died by a signal:
    // -signal).
    std::optional<int> wait(std::chrono::milliseconds timeout);
    void kill(int signal);
    const std::string& log_path() const { return log_; }

private:
    pid_t pid_ = -1;
    std::string log_;
    std::optional<int> exit_;
};

std::string read_file(const std::string& path);
// Polls a log until it contains `needle`; returns the text after it up to the end of its line.
std::optional<std::string> wait_for_text(const std::string& path, const std::string& needle,
                                         std::chrono::milliseconds timeout);
bool files_identical(const std::string& a, const std::string& b);
// Decoded pixels equal bit for bit (file headers may differ).
bool images_identical(const std::string& a, const std::string& b);

}  // namespace pathfarm::test
